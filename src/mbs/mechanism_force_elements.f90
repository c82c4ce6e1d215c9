!> Force elements of ffrf_mbs_mechanism beyond the spring-damper (a submodule): torsion
!> spring-dampers (their state, potential energy, unwrapping references and their restart;
!> ffrf_mbs_torsion_spring, docs/mechanisms.md "Torsion springs") and bushings (state, potential
!> energy; ffrf_mbs_bushing, docs/mechanisms.md "Bushings"); and the generalized forces and
!> tangents of all force elements, springs included, in one loop over force_element_t
!> (ffrf_mbs_force_element). Adding them is in mechanism_build.f90.
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_force_elements
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_force_element, only: force_element_t
   use ffrf_mbs_torsion_spring, only: torsion_evaluate
   use ffrf_mbs_bushing, only: bushing_evaluate
   implicit none

contains

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
   !> (update_torsion_references from the reference 0: each spring's angle depends on its own
   !> reference only.)
   module procedure mechanism_set_torsion_start
      if (.not. allocated(self%torsion_springs)) return
      self%torsion_springs%reference = 0.0_dp
      call update_torsion_references(self, q)
      where (.not. self%torsion_springs%free_angle_given) self%torsion_springs%free_angle = &
         self%torsion_springs%reference
   end procedure mechanism_set_torsion_start

   !> Every torsion spring's unwrapping reference, in order (empty without torsion springs).
   module procedure mechanism_torsion_references
      if (allocated(self%torsion_springs)) then
         references = self%torsion_springs%reference
      else
         allocate (references(0))
      end if
   end procedure mechanism_torsion_references

   !> Every torsion spring's unwrapping reference set from a restart state.
   module procedure mechanism_set_torsion_references
      integer :: count
      count = 0
      if (allocated(self%torsion_springs)) count = size(self%torsion_springs)
      if (size(references) /= count) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'torsion spring references: ' // &
            to_str(size(references)) // ' given for ' // to_str(count) // &
            ' torsion spring(s); give one per &torsion_spring of the case')
         return
      end if
      if (count > 0) self%torsion_springs%reference = references
   end procedure mechanism_set_torsion_references

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

   !> Springs, torsion springs and bushings, in this order (mechanism.f90's interface).
   module procedure add_force_element_terms
      if (allocated(self%springs)) call add_elements(self, self%springs, q, v, t, error, f, &
         K_t, C_t)
      if (allocated(error)) return
      if (allocated(self%torsion_springs)) call add_elements(self, self%torsion_springs, q, v, &
         t, error, f, K_t, C_t)
      if (allocated(error)) return
      if (allocated(self%bushings)) call add_elements(self, self%bushings, q, v, t, error, f, &
         K_t, C_t)
   end procedure add_force_element_terms

   !> Each element's generalized forces added to f (present), or its tangents to K_t and C_t
   !> (both present), at its two bodies' rows (force_element_t%terms).
   subroutine add_elements(self, elements, q, v, t, error, f, K_t, C_t)
      type(mechanism_t), intent(in) :: self
      class(force_element_t), intent(in) :: elements(:)
      real(dp), intent(in) :: q(:), v(:)
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(inout), optional :: f(:)
      type(block_sparse_t), intent(inout), optional :: K_t, C_t
      real(dp), allocatable :: Q_e(:), K(:, :), C(:, :)
      integer, allocatable :: rows(:)
      integer :: s, na, ends(2)
      do s = 1, size(elements)
         ends = elements(s)%bodies()
         call pair_rows(self, ends(1), ends(2), rows, na)
         associate (body_a => self%bodies(ends(1))%body, body_b => self%bodies(ends(2))%body)
            if (present(K_t) .and. present(C_t)) then
               allocate (K(size(rows), size(rows)), C(size(rows), size(rows)))
               call elements(s)%terms(body_a, q(rows(:na)), v(rows(:na)), body_b, &
                  q(rows(na + 1:)), v(rows(na + 1:)), t, error, K=K, C=C)
               if (allocated(error)) return
               call K_t%add(rows, rows, K)
               call C_t%add(rows, rows, C)
               deallocate (K, C)
            else if (present(f)) then
               allocate (Q_e(size(rows)))
               call elements(s)%terms(body_a, q(rows(:na)), v(rows(:na)), body_b, &
                  q(rows(na + 1:)), v(rows(na + 1:)), t, error, Q=Q_e)
               if (allocated(error)) return
               f(rows) = f(rows) + Q_e
               deallocate (Q_e)
            end if
         end associate
      end do
   end subroutine add_elements

end submodule ffrf_mbs_mechanism_force_elements
