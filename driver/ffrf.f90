program ffrf_driver
end program ffrf_driver
