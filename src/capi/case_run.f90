!> Opening, running and closing an ffrf_case_t (a submodule of ffrf_capi_case): the case file
!> read and checked, the modal or mechanism run, the checks of call order they share.
submodule (ffrf_capi_case) ffrf_capi_case_run
   use ffrf_core_error, only: fatal_error, add_context
   use ffrf_core_log, only: stage_times_t, LOG_QUIET
   use ffrf_core_paths, only: folder_of
   use ffrf_input_case, only: read_case
   use ffrf_modes_modal_analysis, only: compute_body_modes
   use ffrf_app_body_modes, only: compute_body_modes_from_file
   use ffrf_model_model, only: model_t, build_model
   use ffrf_core_parallel, only: parallel_of_communicator, use_ranks
   use ffrf_app_modal_run, only: run_modal
   use ffrf_app_mechanism_run, only: run_mechanism
   implicit none

contains

   module procedure quiet_options
      self%log%level = LOG_QUIET
      self%options%log_level = LOG_QUIET
      self%options%mesh_dir = ''
      if (present(mesh_dir)) self%options%mesh_dir = mesh_dir
      self%options%output_dir = ''
      self%write_output = present(output_dir)
      if (present(output_dir)) self%options%output_dir = output_dir
      self%options%restart_file = ''
   end procedure quiet_options

   module procedure case_open
      call quiet_options(self, mesh_dir, output_dir)
      call read_case(case_file, self%case, error)
      if (allocated(error)) return
      self%opened = .true.
   end procedure case_open

   module procedure case_set_communicator
      call check_open(self, 'set_communicator', error)
      if (allocated(error)) return
      if (self%ran .or. self%session%prepared) then
         call bad_call(error, 'set_communicator: the case has run already; set the ' // &
            'communicator before ffrf_case_run and ffrf_mechanism_advance')
         return
      end if
      call parallel_of_communicator(comm, self%options%parallel, error)
   end procedure case_set_communicator

   module procedure bad_call
      call fatal_error(error, FFRF_BAD_CALL, message)
   end procedure bad_call

   module procedure check_open
      if (.not. self%opened) call bad_call(error, what // ': the case is not open ' // &
         '(ffrf_case_open failed or was not called)')
   end procedure check_open

   module procedure mesh_folder
      folder = self%options%mesh_dir
      if (len(folder) == 0) folder = folder_of(self%case%file_name)
   end procedure mesh_folder

   module procedure case_run
      type(stage_times_t) :: times
      type(model_t) :: model
      integer :: k
      call check_open(self, 'run', error)
      if (allocated(error)) return
      if (self%ran) then
         call bad_call(error, 'run: the case has already run')
         return
      end if
      if (self%case%is_mechanism .and. self%session%prepared) then
         if (self%write_output) then
            call bad_call(error, 'run: the mechanism was advanced already; with an output ' &
               // 'folder run writes the whole run from t_start: open the case again')
            return
         end if
      end if
      if (size(self%case%bodies) == 0) then
         call bad_call(error, 'run: the case has no bodies; add one with ffrf_case_add_body')
         return
      end if
      self%ran = .true.
      call use_ranks(self%options%parallel)
      if (.not. self%case%is_mechanism) then
         if (self%write_output) then
            call run_modal(self%case, self%options, self%log, error, self%modes)
         else
            ! as run_modal: the case resolved once by the model (rigid flags, interfaces, modes)
            call build_model(self%case, model, error)
            if (allocated(error)) then
               call add_context(error, self%case%file_name)
               return
            end if
            allocate (self%modes(size(self%case%bodies)))
            do k = 1, size(self%case%bodies)
               if (model%bodies(k)%rigid) cycle
               associate (body => model%bodies(k))
                  if (self%from_arrays) then
                     call attach_node_sets(self, k, body%interfaces)
                     call compute_body_modes(self%meshes(k), body%spec, body%interfaces, &
                        body%modes, self%log, times, self%modes(k), error)
                  else
                     call compute_body_modes_from_file(body%body, body%interfaces, body%modes, &
                        mesh_folder(self), self%log, times, self%modes(k), error)
                  end if
               end associate
               if (allocated(error)) then
                  call add_context(error, self%case%file_name)
                  exit
               end if
            end do
         end if
         self%have_modes = .not. allocated(error)
         return
      end if
      if (self%write_output) then
         call run_mechanism(self%case, self%options, self%log, error, self%modes, &
            self%final_state)
         self%have_final = .true.
         self%have_modes = allocated(self%modes)
         return
      end if
      call self%advance(session_end_time(self), error)
   end procedure case_run

   module procedure session_end_time
      session_end_time = self%case%mechanism%integrator%t_end
   end procedure session_end_time

   module procedure case_is_mechanism
      case_is_mechanism = self%opened .and. self%case%is_mechanism
   end procedure case_is_mechanism

   module procedure case_close
      call self%session%finish()
      call reset(self)
   contains
      subroutine reset(self)
         class(ffrf_case_t), intent(out) :: self
         self%opened = .false.
      end subroutine reset
   end procedure case_close

end submodule ffrf_capi_case_run
