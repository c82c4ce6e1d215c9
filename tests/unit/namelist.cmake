# Strict case reading (owner: input): the echo of every input/*.nml unchanged, the pre-parser's
# canonical text, key locations and structural errors. Reads no mesh; well under a second.
ffrf_add_unit_suite(test_io_namelist CHECKED)
