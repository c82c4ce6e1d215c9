!> The energy watch of a mechanism run (a submodule of ffrf_app_mechanism_output): started,
!> fed each step with the bodies' energies, its warnings written to the results file.
submodule (ffrf_app_mechanism_output) ffrf_app_mechanism_output_watch
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_flexible_body, only: flexible_body_t
   implicit none

contains

   module procedure start_watch
      character(len=64), allocatable :: names(:)
      logical, allocatable :: flexible(:)
      real(dp), allocatable :: kinetic(:), strain(:)
      integer :: b, n
      n = size(mech%bodies)
      allocate (names(n), flexible(n))
      do b = 1, n
         names(b) = mech%bodies(b)%name
         select type (body => mech%bodies(b)%body)
         class is (flexible_body_t)
            flexible(b) = .true.
         class default
            flexible(b) = .false.
         end select
      end do
      call body_energies(mech, integrator%q, integrator%v, kinetic, strain)
      call self%watch%init(resolved%mechanism%energy_watch, integrator%t, names, flexible, &
         kinetic + strain, error)
   end procedure start_watch

   !> T_b and U_b of every body of the mechanism at (q, v) (J).
   subroutine body_energies(mech, q, v, kinetic, strain)
      type(mechanism_t), intent(in) :: mech
      real(dp), intent(in) :: q(:), v(:)
      real(dp), allocatable, intent(out) :: kinetic(:), strain(:)
      integer :: b, k, nb
      allocate (kinetic(size(mech%bodies)), strain(size(mech%bodies)))
      kinetic = 0.0_dp
      strain = 0.0_dp
      do b = 1, size(mech%bodies)
         k = mech%bodies(b)%offset
         nb = mech%bodies(b)%body%num_coordinates
         if (nb == 0) cycle
         kinetic(b) = mech%bodies(b)%body%kinetic_energy(q(k + 1:k + nb), v(k + 1:k + nb))
         strain(b) = mech%bodies(b)%body%strain_energy(q(k + 1:k + nb))
      end do
   end subroutine body_energies

   module procedure watch_step
      real(dp), allocatable :: kinetic(:), strain(:)
      character(len=:), allocatable :: text, body
      real(dp) :: t
      logical :: new_warning
      call body_energies(mech, integrator%q, integrator%v, kinetic, strain)
      associate (b => self%balance)
         call self%watch%check(b%t, b%kinetic, b%strain, b%work, b%physical_dissipation, &
            b%numerical_dissipation, b%scheme_dissipation, b%has_scheme, kinetic, strain, &
            new_warning, error)
      end associate
      if (new_warning .and. .not. allocated(error)) then
         call self%watch%warning(self%watch%count(), text, t, body)
         call log%note('energy', 'warning: ' // text)
      end if
   end procedure watch_step

   module procedure write_warnings
      character(len=:), allocatable :: text, body
      character(len=1024), allocatable :: texts(:)
      character(len=64), allocatable :: bodies(:)
      real(dp), allocatable :: times(:)
      integer :: k, n
      if (.not. allocated(watch%names)) return
      n = watch%count()
      call log%info('energy', 'watch: largest spurious energy -D_s = ' // &
         to_str(watch%worst_ratio, 3) // ' of the energy scale (t = ' // &
         to_str(watch%worst_time, 6) // ' s; tolerance ' // &
         to_str(watch%settings%tolerance, 3) // '), ' // to_str(n) // ' warning(s)')
      if (n == 0) return
      allocate (texts(n), bodies(n), times(n))
      do k = 1, n
         call watch%warning(k, text, times(k), body)
         texts(k) = text
         bodies(k) = body
      end do
      call results%write_strings('/warnings/text', texts, error)
      if (.not. allocated(error)) call results%write_real('/warnings/time', times, 's', error)
      if (.not. allocated(error)) call results%write_strings('/warnings/body', bodies, error)
   end procedure write_warnings

end submodule ffrf_app_mechanism_output_watch
