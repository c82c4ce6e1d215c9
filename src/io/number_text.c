/* Text of numbers, byte for byte as gfortran's formatted output writes them with the edit
 * descriptors ESw.dE3 (w = d + 8: one significant digit before the point, d after, exponent
 * E+NNN, right-justified) and I0, for writers that build large ASCII files in memory
 * (ffrf_io_text_stream). gfortran rounds ES output as printf's %E does (the exact binary value,
 * ties to even: glibc); this file gets the same digits from an extended-precision product and
 * calls snprintf whenever that product cannot decide the rounding for sure. Nothing here
 * allocates, prints or exits, and the floating-point exception flags are left as they were (a
 * subnormal operand raises the denormal flag, which a later Fortran STOP would report). */
#include <fenv.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_DIGITS = 17 };

/* 10^k, exact in a long double of >= 64 significand bits (5^27 < 2^63) */
static const long double exact_power_of_ten[28] = {
    1e0L, 1e1L, 1e2L, 1e3L, 1e4L, 1e5L, 1e6L, 1e7L, 1e8L, 1e9L, 1e10L, 1e11L, 1e12L, 1e13L,
    1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L, 1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L,
    1e27L};

/* Digits and decimal exponent of `magnitude` (> 0, finite) rounded to `digits` significant
 * digits by snprintf (%.*E: the exact value, ties to even). */
static void digits_by_printf(double magnitude, int digits, char *digit_text, int *exponent)
{
    char text[64];
    int i, n = 0;
    snprintf(text, sizeof text, "%.*E", digits - 1, magnitude);
    for (i = 0; text[i] != 'E'; ++i)
        if (text[i] != '.') digit_text[n++] = text[i];
    *exponent = (int)strtol(text + i + 1, NULL, 10);
}

#if LDBL_MANT_DIG >= 64
/* magnitude * 10^power in long double; *operations: the roundings it took (each one relative
 * error <= LDBL_EPSILON / 2) */
static long double scaled(double magnitude, int power, int *operations)
{
    long double s = (long double)magnitude;
    *operations = 0;
    while (power > 27) {
        s *= exact_power_of_ten[27];
        power -= 27;
        ++*operations;
    }
    while (power < -27) {
        s /= exact_power_of_ten[27];
        power += 27;
        ++*operations;
    }
    if (power > 0) s *= exact_power_of_ten[power];
    if (power < 0) s /= exact_power_of_ten[-power];
    if (power != 0) ++*operations;
    return s;
}
#endif

/* Digits (`digits` characters, no point) and decimal exponent of `magnitude` (> 0, finite)
 * rounded to `digits` (<= 17) significant digits, as snprintf's %.*E rounds. The significand
 * s = magnitude * 10^(digits - 1 - exponent) in [10^(digits-1), 10^digits) is formed in long
 * double with a bound on its rounding error; when the bound leaves the rounding (or the
 * exponent) undecided, snprintf decides. */
static void decimal_digits(double magnitude, int digits, char *digit_text, int *exponent)
{
#if LDBL_MANT_DIG >= 64
    const long double low = exact_power_of_ten[digits - 1], high = exact_power_of_ten[digits];
    int e10 = (int)floor(log10(magnitude)), operations, attempt;
    for (attempt = 0; attempt < 3; ++attempt) {
        long double s = scaled(magnitude, digits - 1 - e10, &operations);
        long double bound = (operations + 1) * LDBL_EPSILON * s, fraction;
        uint64_t q;
        int i;
        if (s < low) {
            --e10;
            continue;
        }
        if (s >= high) {
            ++e10;
            continue;
        }
        /* undecided: the exponent (just above 10^(digits-1)) or a tie */
        if (s - low < bound) break;
        q = (uint64_t)s;
        fraction = s - (long double)q;
        if (fabsl(fraction - 0.5L) <= bound) break;
        if (fraction > 0.5L) ++q;
        if ((long double)q == high) {
            q /= 10;
            ++e10;
        }
        for (i = digits - 1; i >= 0; --i) {
            digit_text[i] = (char)('0' + q % 10);
            q /= 10;
        }
        *exponent = e10;
        return;
    }
#endif
    digits_by_printf(magnitude, digits, digit_text, exponent);
}

/* ffrf_format_es_e3 without saving the floating-point environment */
static void format_es_e3(double value, int digits, char *out)
{
    const int width = digits + 7;
    char text[MAX_DIGITS + 16], digit_text[MAX_DIGITS];
    int n = 0, exponent = 0, i;
    if (digits < 1 || digits > MAX_DIGITS) {
        memset(out, '*', (size_t)(width > 0 ? width : 0));
        return;
    }
    if (isnan(value)) {
        n = snprintf(text, sizeof text, "NaN");
    } else if (isinf(value)) {
        n = snprintf(text, sizeof text, "%s", value < 0 ? "-Infinity" : "Infinity");
    } else {
        if (signbit(value)) text[n++] = '-';
        if (value == 0.0) {
            memset(digit_text, '0', (size_t)digits);
        } else {
            decimal_digits(fabs(value), digits, digit_text, &exponent);
        }
        text[n++] = digit_text[0];
        text[n++] = '.';
        for (i = 1; i < digits; ++i) text[n++] = digit_text[i];
        text[n++] = 'E';
        text[n++] = exponent < 0 ? '-' : '+';
        if (exponent < 0) exponent = -exponent;
        text[n++] = (char)('0' + exponent / 100);
        text[n++] = (char)('0' + exponent / 10 % 10);
        text[n++] = (char)('0' + exponent % 10);
    }
    memset(out, ' ', (size_t)(width - n));
    memcpy(out + (width - n), text, (size_t)n);
}

/* `value` as gfortran's ES(digits + 7).(digits - 1)E3 writes it: exactly digits + 7
 * characters at `out`, blank-padded on the left. NaN and Inf as gfortran writes them. */
void ffrf_format_es_e3(double value, int digits, char *out)
{
    fenv_t environment;
    feholdexcept(&environment);
    format_es_e3(value, digits, out);
    fesetenv(&environment);
}

/* `value` as I0 writes it; returns the number of characters (at most 11). */
static int format_i0(int value, char *out)
{
    char reversed[12];
    int n = 0, i, length = 0;
    long long magnitude = value;
    if (magnitude < 0) {
        out[length++] = '-';
        magnitude = -magnitude;
    }
    do {
        reversed[n++] = (char)('0' + magnitude % 10);
        magnitude /= 10;
    } while (magnitude > 0);
    for (i = n - 1; i >= 0; --i) out[length++] = reversed[i];
    return length;
}

/* `count` integers as '(*(i0, :, 1x))' writes them, then a newline; returns the bytes written
 * (at most 12 * count + 1). */
int64_t ffrf_format_i0_line(int count, const int *values, char *out)
{
    int64_t n = 0;
    int i;
    for (i = 0; i < count; ++i) {
        if (i > 0) out[n++] = ' ';
        n += format_i0(values[i], out + n);
    }
    out[n++] = '\n';
    return n;
}

/* `num_lines` lines as '(i0, 3(1x, esW.DE3))' writes them (W = digits + 7, D = digits - 1):
 * line i (0-based) is the tag first_tag + i and values[3i .. 3i+2]; returns the bytes written
 * (at most num_lines * (12 + 3 * (digits + 8))). */
int64_t ffrf_format_tagged_es_lines(int first_tag, int num_lines, const double *values,
                                    int digits, char *out)
{
    const int width = digits + 7;
    int64_t n = 0;
    int line, k;
    fenv_t environment;
    feholdexcept(&environment);
    for (line = 0; line < num_lines; ++line) {
        n += format_i0(first_tag + line, out + n);
        for (k = 0; k < 3; ++k) {
            out[n++] = ' ';
            format_es_e3(values[3 * (int64_t)line + k], digits, out + n);
            n += width;
        }
        out[n++] = '\n';
    }
    fesetenv(&environment);
    return n;
}
