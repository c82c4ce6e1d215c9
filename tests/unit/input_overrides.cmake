# Batch command line, input layer (owner: input): --set override syntax and injection (the
# namelist's own checks and messages), sweep table rows, output templates, task index. Reads no
# mesh; well under a second.
ffrf_add_unit_suite(test_input_overrides CHECKED LABELS input)
