!> Force elements of ffrf_mbs_mechanism beyond the spring-damper (a submodule): torsion
!> spring-dampers (adding them about a joint, their state, potential energy, unwrapping
!> references, generalized forces and exact tangents; ffrf_mbs_torsion_spring,
!> docs/mechanisms.md "Torsion springs") and bushings (ffrf_mbs_bushing, docs/mechanisms.md
!> "Bushings").
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_force_elements
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_torsion_spring, only: torsion_evaluate, torsion_tangents
   use ffrf_mbs_spring_damper, only: marker_pair_forces
   use ffrf_mbs_bushing, only: bushing_evaluate, bushing_generalized_forces, bushing_tangents
   implicit none

contains

   !> Add a copy of a torsion spring about a revolute or cylindrical joint.
   module procedure mechanism_add_torsion_spring
      type(torsion_spring_t) :: added
      integer :: nj
      character(len=:), allocatable :: where
      where = 'mechanism: torsion spring "' // trim(spring%name) // '"'
      nj = 0
      if (allocated(self%joints)) nj = size(self%joints)
      if (spring%joint < 1 .or. spring%joint > nj) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': the mechanism has no joint ' // &
            to_str(spring%joint) // ' (' // to_str(nj) // ' joints)')
         return
      end if
      associate (jt => self%joints(spring%joint))
         select case (jt%joint%kind_name())
         case ('revolute', 'cylindrical')
         case default
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': joint "' // jt%name // &
               '" is ' // jt%joint%kind_name() // '; a torsion spring needs a revolute or ' // &
               'cylindrical joint')
            return
         end select
         if (.not. (spring%stiffness >= 0.0_dp .and. spring%damping >= 0.0_dp)) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // ': stiffness = ' // &
               to_str(spring%stiffness) // ' N m/rad and damping = ' // &
               to_str(spring%damping) // ' N m s/rad; both must be >= 0')
            return
         end if
         added = spring
         added%body_a = jt%body_a
         added%body_b = jt%body_b
         added%marker_a = jt%joint%marker_a
         added%marker_b = jt%joint%marker_b
      end associate
      if (.not. allocated(self%torsion_springs)) allocate (self%torsion_springs(0))
      self%torsion_springs = [self%torsion_springs, added]
   end procedure mechanism_add_torsion_spring

   !> Angle, rate and torque of torsion spring s at (q, v).
   module procedure mechanism_torsion_state
      integer, allocatable :: rows(:)
      integer :: na
      associate (spring => self%torsion_springs(s))
         call pair_rows(self, spring%body_a, spring%body_b, rows, na)
         state = torsion_evaluate(spring, self%bodies(spring%body_a)%body, q(rows(:na)), &
            v(rows(:na)), self%bodies(spring%body_b)%body, q(rows(na + 1:)), v(rows(na + 1:)))
      end associate
   end procedure mechanism_torsion_state

   !> Potential energy of the torsion springs, sum k (phi - phi0)^2 / 2 (J).
   module procedure mechanism_torsion_energy
      type(torsion_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      energy = 0.0_dp
      if (.not. allocated(self%torsion_springs)) return
      zero = 0.0_dp
      do s = 1, size(self%torsion_springs)
         state = self%torsion_state(s, q, zero)
         energy = energy + 0.5_dp * self%torsion_springs(s)%stiffness * &
            (state%angle - self%torsion_springs(s)%free_angle)**2
      end do
   end procedure mechanism_torsion_energy

   !> Unwrapping references from the start, in (-pi, pi]; free angles not given from the start.
   module procedure mechanism_set_torsion_start
      type(torsion_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      if (.not. allocated(self%torsion_springs)) return
      zero = 0.0_dp
      do s = 1, size(self%torsion_springs)
         self%torsion_springs(s)%reference = 0.0_dp
         state = self%torsion_state(s, q, zero)
         self%torsion_springs(s)%reference = state%angle
         if (.not. self%torsion_springs(s)%free_angle_given) &
            self%torsion_springs(s)%free_angle = state%angle
      end do
   end procedure mechanism_set_torsion_start

   !> The torsion springs' generalized forces (f present) or exact tangents (K_t, C_t present;
   !> ffrf_mbs_torsion_spring).
   module procedure add_torsion_terms
      type(torsion_state_t) :: state
      real(dp), allocatable :: f_a(:), f_b(:), K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, na
      if (.not. allocated(self%torsion_springs)) return
      do s = 1, size(self%torsion_springs)
         associate (spring => self%torsion_springs(s), body_a => &
               self%bodies(self%torsion_springs(s)%body_a)%body, &
               body_b => self%bodies(self%torsion_springs(s)%body_b)%body)
            state = self%torsion_state(s, q, v)
            if (.not. ieee_is_finite(state%torque)) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'torsion spring "' // &
                  trim(spring%name) // '": torque ' // to_str(state%torque) // ' N m at t = ' &
                  // to_str(t) // ' s (angle ' // to_str(state%angle) // ' rad); a torsion ' &
                  // 'spring needs finite joint frames')
               return
            end if
            call pair_rows(self, spring%body_a, spring%body_b, rows, na)
            if (present(K_t) .and. present(C_t)) then
               allocate (K(size(rows), size(rows)), C(size(rows), size(rows)))
               call torsion_tangents(spring, state, body_a, q(rows(:na)), v(rows(:na)), &
                  body_b, q(rows(na + 1:)), v(rows(na + 1:)), K, C)
               call add_pair_tangents(rows, K, C, K_t, C_t)
               deallocate (K, C)
            else if (present(f)) then
               allocate (f_a(na), f_b(size(rows) - na))
               ! the moment -T z_a on marker a, +T z_a on marker b (ffrf_mbs_torsion_spring)
               call marker_pair_forces(body_a, q(rows(:na)), spring%marker_a, body_b, &
                  q(rows(na + 1:)), spring%marker_b, [0.0_dp, 0.0_dp, 0.0_dp], &
                  -state%torque * state%axis, f_a, f_b)
               f(rows) = f(rows) + [f_a, f_b]
               deallocate (f_a, f_b)
            end if
         end associate
      end do
   end procedure add_torsion_terms

   !> The angle at an accepted step becomes each torsion spring's unwrapping reference.
   module procedure update_torsion_references
      type(torsion_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      if (.not. allocated(self%torsion_springs)) return
      zero = 0.0_dp
      do s = 1, size(self%torsion_springs)
         state = self%torsion_state(s, q, zero)
         self%torsion_springs(s)%reference = state%angle
      end do
   end procedure update_torsion_references

   !> Add a copy of a bushing between two markers of two bodies.
   module procedure mechanism_add_bushing
      character(len=:), allocatable :: where
      integer :: nb
      where = 'mechanism: bushing "' // trim(bushing%name) // '"'
      nb = 0
      if (allocated(self%bodies)) nb = size(self%bodies)
      if (min(bushing%body_a, bushing%body_b) < 1 .or. max(bushing%body_a, bushing%body_b) &
         > nb) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': the mechanism has no body ' // &
            to_str(bushing%body_a) // ' or ' // to_str(bushing%body_b) // ' (' // to_str(nb) &
            // ' bodies)')
      else if (bushing%body_a == bushing%body_b) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': both markers are on body "' // &
            self%bodies(bushing%body_a)%name // '"; a bushing connects two different bodies')
      else if (bushing%marker_a < 1 .or. bushing%marker_a > &
         self%bodies(bushing%body_a)%body%num_markers .or. bushing%marker_b < 1 .or. &
         bushing%marker_b > self%bodies(bushing%body_b)%body%num_markers) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': no marker ' // &
            to_str(bushing%marker_a) // ' or ' // to_str(bushing%marker_b) // &
            ' on its bodies')
      else if (.not. (all(bushing%stiffness >= 0.0_dp) .and. &
         all(bushing%damping >= 0.0_dp))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // ': a negative stiffness or ' // &
            'damping entry; all six of each must be >= 0')
      end if
      if (allocated(error)) return
      if (.not. allocated(self%bushings)) allocate (self%bushings(0))
      self%bushings = [self%bushings, bushing]
   end procedure mechanism_add_bushing

   !> Deflections, rates and element force of bushing s at (q, v).
   module procedure mechanism_bushing_state
      integer, allocatable :: rows(:)
      integer :: na
      associate (bushing => self%bushings(s))
         call pair_rows(self, bushing%body_a, bushing%body_b, rows, na)
         state = bushing_evaluate(bushing, self%bodies(bushing%body_a)%body, q(rows(:na)), &
            v(rows(:na)), self%bodies(bushing%body_b)%body, q(rows(na + 1:)), v(rows(na + 1:)))
      end associate
   end procedure mechanism_bushing_state

   !> Potential energy of the bushings, sum e^T K e / 2 (J).
   module procedure mechanism_bushing_energy
      type(bushing_state_t) :: state
      real(dp) :: zero(size(q))
      integer :: s
      energy = 0.0_dp
      if (.not. allocated(self%bushings)) return
      zero = 0.0_dp
      do s = 1, size(self%bushings)
         state = self%bushing_state(s, q, zero)
         energy = energy + 0.5_dp * sum(self%bushings(s)%stiffness * state%deflection**2)
      end do
   end procedure mechanism_bushing_energy

   !> The bushings' generalized forces (f present) or tangents (K_t, C_t present;
   !> ffrf_mbs_bushing).
   module procedure add_bushing_terms
      type(bushing_state_t) :: state
      real(dp), allocatable :: f_a(:), f_b(:), K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, na
      if (.not. allocated(self%bushings)) return
      do s = 1, size(self%bushings)
         associate (bushing => self%bushings(s), body_a => &
               self%bodies(self%bushings(s)%body_a)%body, &
               body_b => self%bodies(self%bushings(s)%body_b)%body)
            state = self%bushing_state(s, q, v)
            if (.not. all(ieee_is_finite(state%force))) then
               call fatal_error(error, FFRF_NUMERIC_ERROR, 'bushing "' // trim(bushing%name) &
                  // '": force not finite at t = ' // to_str(t) // ' s; a bushing needs ' // &
                  'finite marker frames')
               return
            end if
            call pair_rows(self, bushing%body_a, bushing%body_b, rows, na)
            if (present(K_t) .and. present(C_t)) then
               allocate (K(size(rows), size(rows)), C(size(rows), size(rows)))
               call bushing_tangents(bushing, body_a, q(rows(:na)), v(rows(:na)), body_b, &
                  q(rows(na + 1:)), v(rows(na + 1:)), K, C)
               call add_pair_tangents(rows, K, C, K_t, C_t)
               deallocate (K, C)
            else if (present(f)) then
               allocate (f_a(na), f_b(size(rows) - na))
               call bushing_generalized_forces(bushing, body_a, q(rows(:na)), v(rows(:na)), &
                  body_b, q(rows(na + 1:)), v(rows(na + 1:)), f_a, f_b)
               f(rows) = f(rows) + [f_a, f_b]
               deallocate (f_a, f_b)
            end if
         end associate
      end do
   end procedure add_bushing_terms

   !> Rows of bodies a and b in the mechanism's coordinates ([a's; b's]) and the number of a's.
   subroutine pair_rows(self, body_a, body_b, rows, na)
      type(mechanism_t), intent(in) :: self
      integer, intent(in) :: body_a, body_b
      integer, allocatable, intent(out) :: rows(:)
      integer, intent(out) :: na
      integer :: i
      na = self%bodies(body_a)%body%num_coordinates
      rows = [(self%bodies(body_a)%offset + i, i = 1, na), (self%bodies(body_b)%offset + i, &
         i = 1, self%bodies(body_b)%body%num_coordinates)]
   end subroutine pair_rows

   !> K_t(rows, rows) += K, C_t(rows, rows) += C.
   pure subroutine add_pair_tangents(rows, K, C, K_t, C_t)
      integer, intent(in) :: rows(:)
      real(dp), intent(in) :: K(:, :), C(:, :)
      real(dp), intent(inout) :: K_t(:, :), C_t(:, :)
      K_t(rows, rows) = K_t(rows, rows) + K
      C_t(rows, rows) = C_t(rows, rows) + C
   end subroutine add_pair_tangents

end submodule ffrf_mbs_mechanism_force_elements
