!> `use ffrf` gives the public API of the library.
module ffrf
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR, &
      FFRF_IO_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_log, only: logger_t, LOG_QUIET, LOG_INFO, LOG_DEBUG
   implicit none
   public
end module ffrf
