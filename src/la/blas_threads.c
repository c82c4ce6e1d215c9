/* Threads of the BLAS: OpenBLAS's openblas_set_num_threads/openblas_get_num_threads when the
 * BLAS linked is OpenBLAS (weak references: another BLAS links too, and is then left alone). */
void openblas_set_num_threads(int) __attribute__((weak));
int openblas_get_num_threads(void) __attribute__((weak));

/* Set the BLAS threads to n (n >= 1); returns the threads the BLAS then uses, -1 when the BLAS
 * linked has no such control (not OpenBLAS). */
int ffrf_blas_set_threads(int n)
{
    if (!openblas_set_num_threads || !openblas_get_num_threads) return -1;
    openblas_set_num_threads(n);
    return openblas_get_num_threads();
}

/* The threads the BLAS uses, -1 when unknown (not OpenBLAS). */
int ffrf_blas_threads(void)
{
    return openblas_get_num_threads ? openblas_get_num_threads() : -1;
}
