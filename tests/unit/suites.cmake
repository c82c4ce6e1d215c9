# unit suites, one line each: ffrf_add_unit_suite(test_<family>_<thing> ...)
