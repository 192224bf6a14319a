/* SPDX-License-Identifier: MIT */
/*
 * Shortest round-trip formatting (see pfh_fmt.h), built on the C library's
 * correctly rounded conversions (glibc's printf and strtod are exact)
 * rather than a digit-generation algorithm of our own.
 *
 * For p significant digits let M_p be v correctly rounded to p digits
 * ("%.*e"). M_p is the p-digit decimal nearest v, so if any p-digit decimal
 * reads back as v, the interval of decimals that read back as v contains
 * either M_p or, where it is lopsided (v a power of two: the gap below is
 * half the gap above), the p-digit neighbour of M_p on the wide side; and a
 * decimal that round-trips with p digits round-trips with p + 1. So: binary
 * search for the smallest p whose M_p reads back, then try M_{p-1} +- 1
 * unit in the last place, the only (p-1)-digit decimals that can still read
 * back. 17 digits always suffice for a double, 9 for a float.
 */
#include "pfh_fmt.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A decimal: mant * 10^e10, mant < 10^17. */
typedef struct dec {
    long long mant;
    int e10;
} dec;

/* v correctly rounded to p significant digits (v finite, not 0). */
static dec round_to(double v, int p)
{
    char s[40];
    const char *c;
    dec d = {0, 0};
    int e;
    snprintf(s, sizeof s, "%.*e", p - 1, fabs(v));
    for (c = s; *c != 'e'; c++)
        if (*c >= '0' && *c <= '9')
            d.mant = d.mant * 10 + (*c - '0');
    e = atoi(c + 1);
    d.e10 = e - (p - 1);
    return d;
}

static int reads_back(dec d, double v, int is_float)
{
    char s[48];
    snprintf(s, sizeof s, "%s%llde%d", v < 0 ? "-" : "", d.mant, d.e10);
    if (is_float)
        return strtof(s, NULL) == (float)v;
    return strtod(s, NULL) == v;
}

static dec shortest(double v, int is_float)
{
    int lo = 1, hi = is_float ? 9 : 17;
    dec best, up, down;
    /* Smallest p in [lo, hi] whose rounding reads back (hi always does). */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (reads_back(round_to(v, mid), v, is_float))
            hi = mid;
        else
            lo = mid + 1;
    }
    best = round_to(v, lo);
    if (lo > 1) {
        dec m = round_to(v, lo - 1);
        up = m;
        down = m;
        up.mant++;
        down.mant--;
        if (down.mant > 0 && reads_back(down, v, is_float))
            best = down;
        else if (reads_back(up, v, is_float))
            best = up;
    }
    return best;
}

/* Lay out digits (no trailing zeros) with decimal exponent x of the first
 * digit, as Python's repr does. */
static int layout(char *buf, int neg, const char *dig, int n, int x)
{
    char *o = buf;
    int i;
    if (neg)
        *o++ = '-';
    if (x >= -4 && x < 16) {
        if (x < 0) {
            *o++ = '0';
            *o++ = '.';
            for (i = 0; i < -x - 1; i++)
                *o++ = '0';
            memcpy(o, dig, (size_t)n);
            o += n;
        } else {
            for (i = 0; i <= x; i++)
                *o++ = i < n ? dig[i] : '0';
            if (n > x + 1) {
                *o++ = '.';
                memcpy(o, dig + x + 1, (size_t)(n - x - 1));
                o += n - x - 1;
            }
        }
        *o = '\0';
    } else {
        *o++ = dig[0];
        if (n > 1) {
            *o++ = '.';
            memcpy(o, dig + 1, (size_t)(n - 1));
            o += n - 1;
        }
        o += sprintf(o, "e%c%02d", x < 0 ? '-' : '+', x < 0 ? -x : x);
    }
    return (int)(o - buf);
}

static int fmt(char *buf, double v, int is_float)
{
    char dig[24];
    dec d;
    int n;
    if (isnan(v))
        return sprintf(buf, "nan");
    if (isinf(v))
        return sprintf(buf, v < 0 ? "-inf" : "inf");
    if (v == 0)
        return sprintf(buf, signbit(v) ? "-0" : "0");
    d = shortest(v, is_float);
    while (d.mant % 10 == 0) {
        d.mant /= 10;
        d.e10++;
    }
    n = sprintf(dig, "%lld", d.mant);
    return layout(buf, v < 0, dig, n, d.e10 + n - 1);
}

int pfh_fmt_double(char buf[PFH_FMT_LEN], double v)
{
    return fmt(buf, v, 0);
}

int pfh_fmt_float(char buf[PFH_FMT_LEN], float v)
{
    return fmt(buf, (double)v, 1);
}

int pfh_fput_double(FILE *f, double v)
{
    char b[PFH_FMT_LEN];
    pfh_fmt_double(b, v);
    return fputs(b, f);
}
