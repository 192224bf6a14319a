/* SPDX-License-Identifier: MIT */
/*
 * Exact reference transfer functions and step responses (see pfh_ref.h).
 *
 * Transfer function (Figures 3, 5, 7 of the paper; block-diagram algebra):
 *   u = (tau s)^beta,  R = (1 + u) / (pmin + pmax u)          relay, eq. 14
 *   B = (A/ks) s^-q                                            bellows, eq. 16
 *   M = 1 (p), Rv (dd), 1 - Rw (id), Rv - Rw (pid), Rv = 1/(RC s^nu + 1),
 *       Rw = 1/(RC s^w + 1); pid uses RCd in Rv and RCi in Rw
 *   H = g R / (1 + c R B M),  g = b k1 k2/(a+b),  c = a k1 k2/(a+b)
 *
 * Why this is the paper's eq. 17, 18, 20: multiply numerator and denominator
 * of H by (a+b) ks s^q (pmin + pmax u) and, for dd/id, by (RC s^x + 1):
 *   p : H = b k1 k2 ks s^q (1+u)
 *         / [(a+b) ks s^q (pmin+pmax u) + a A k1 k2 (1+u)]             = (17)
 *   dd: H = b k1 k2 ks s^q (RC s^nu+1)(1+u)
 *         / [(a+b) ks s^q (RC s^nu+1)(pmin+pmax u) + a A k1 k2 (1+u)]
 *       and expanding the products with K = k1 k2 ks b, kappa = ks (a+b),
 *       eta = k1 k2 a A gives the last line of (18) term by term (the
 *       middle line of (18) as printed misplaces a bracket; its first and
 *       last lines agree with H).
 *   id: 1 - Rw = RC s^w/(RC s^w+1), so
 *       H = b k1 k2 ks s^q (RC s^w+1)(1+u)
 *         / [(a+b) ks s^q (RC s^w+1)(pmin+pmax u) + a A k1 k2 RC s^w (1+u)] = (20)
 * (tau s)^beta = tau^beta s^beta and s^x s^y = s^(x+y) hold exactly on the
 * principal branch for tau > 0, so the paper's monomials agree with ours.
 * test_reference.c checks these identities numerically.
 *
 * Singularities of H(s)/s, for the paper's ten cases in paper_step_cases.json
 * (checked numerically: Newton root search in x = Log s plus an argument-
 * principle count over |Im x| < pi, |Re x| < 30, i.e. the whole principal
 * sheet with 1e-13 < |s| < 1e13):
 *  - branch point at s = 0, cut along the negative real axis;
 *  - R's pole, (tau s)^beta = -pmin/pmax, needs arg s = pi/beta: off the
 *    principal sheet for beta < 1; for beta = 1 it is removable in H;
 *  - poles of H = zeros of the cleared denominator above:
 *      ex4_q0.9, ex4_q0.99, ex4_beta0.6, ex4_beta0.8, ex6_q0.9, ex6_q0.99,
 *      ex7: none;
 *      ex4_q1.0: s = -1.000018e-4 +- 1.33e-9 i;
 *      ex6_q1.0: s = -1.000035e-4 +- 1.65e-9 i;
 *      ex4_beta1.0: s = -99.999864 +- 4.41e-5 i (relay pole shifted by the
 *        bellows loop).
 *    These are simple poles in Re s < 0 with |Im s| < 2e-5 |s|: for the
 *    contour below they act like points of the cut. The contour wraps the
 *    negative axis (it crosses the real axis only at +0.171 N/t and its
 *    untruncated strands tend to Im z = +-1.297 N/t), so they are always
 *    enclosed; when a pole lies left of the truncation point -1.358 N/t its
 *    share is within the truncation error bound. Nothing lies in Re s >= 0.
 */
#include "pfh_ref.h"

#include <math.h>
#include <stddef.h>

/* Principal power s^e = exp(e Log s). Exponents 0 and 1 are exact so that
 * q = 0 (linear spring) and beta = q = 1 give the rational special cases. */
static double complex ppow(double complex s, double e)
{
    if (e == 0.0)
        return 1.0;
    if (e == 1.0)
        return s;
    return cexp(e * clog(s));
}

double complex pfh_ref_tf(const pf_params *p, double complex s)
{
    const double g = p->b * p->k1 * p->k2 / (p->a + p->b);
    const double c = p->a * p->k1 * p->k2 / (p->a + p->b);
    const double complex u = ppow(p->tau * s, p->beta);
    const double complex R = (1.0 + u) / (p->pmin + p->pmax * u);
    const double complex B = (p->A / p->ks) / ppow(s, p->q);
    double complex M = 1.0;
    double complex xd, xi;

    /* 1 - 1/(x+1) and Rv - Rw are written over a common denominator so that
     * no digits cancel when |RC s^x| is small (large t); it is the same
     * function. */
    switch (p->topology) {
    case PF_TOPO_DD:
        M = 1.0 / (p->RC * ppow(s, p->nu) + 1.0);
        break;
    case PF_TOPO_ID:
        xi = p->RC * ppow(s, p->w);
        M = xi / (xi + 1.0);
        break;
    case PF_TOPO_PID:
        xd = p->RCd * ppow(s, p->nu);
        xi = p->RCi * ppow(s, p->w);
        M = (xi - xd) / ((xd + 1.0) * (xi + 1.0));
        break;
    default: /* PF_TOPO_P */
        break;
    }
    return g * R / (1.0 + c * R * B * M);
}

/*
 * Inverse Laplace transform on a Talbot-type contour, trapezoid/midpoint
 * rule in the contour parameter theta (formula only; no code copied):
 *   z(theta) = (N/t) (mu theta cot(alpha theta) - sigma + i nu theta),
 *   mu = 0.5017, alpha = 0.6407, sigma = 0.6122, nu = 0.2645,
 *   f(t) ~ (1/(2 pi i)) sum_{k=1..N} e^{z_k t} F(z_k) z'(theta_k) 2pi/N,
 *   theta_k = -pi + (k - 1/2) 2pi/N,
 * the optimized cotangent contour of L. N. Trefethen, J. A. C. Weideman and
 * T. Schmelzer, "Talbot quadratures and rational approximations", BIT Numer.
 * Math. 46 (2006) 653-670 (parameters from J. A. C. Weideman, "Optimizing
 * Talbot's contours for the inversion of the Laplace transform", SIAM J.
 * Numer. Anal. 44 (2006) 2342-2362). For F analytic off (-inf, 0] the error
 * is O(3.89^-N); rounding is amplified by about max|e^{zt}| = e^{0.171 N}.
 * Why N = 32: discretization ~1e-19, rounding ~300 eps ~ 1e-13 relative.
 * Measured against paper_step_exact.csv the error stops decreasing at
 * N = 24 (1e-6 at N = 12, 7e-9 at N = 16); N = 32 leaves margin for other
 * parameter sets at no noticeable cost.
 *
 * F(conj z) = conj F(z) and z(-theta) = conj z(theta), z'(-theta) =
 * -conj z'(theta), so the terms pair up as 2i Im(.) and, with h = 2pi/N,
 *   f(t) = (2/N) sum_{k: theta_k > 0} Im(e^{z_k t} F(z_k) z'(theta_k)),
 *   z'(theta) = (N/t)(mu (cot(alpha theta) - alpha theta / sin^2(alpha
 *   theta)) + i nu).
 */
/* F(z) = H(z)/z, or H(z) line(z)/z with the lag of the output line. */
typedef struct step_tf {
    const pf_params *p;
    double lag;
} step_tf;

static double complex step_transform(const step_tf *f, double complex z)
{
    double complex h = pfh_ref_tf(f->p, z) / z;
    return f->lag > 0.0 ? h / (1.0 + f->lag * z) : h;
}

static double talbot(const step_tf *f, double t, int n)
{
    const double mu = 0.5017, alpha = 0.6407, sigma = 0.6122, nu = 0.2645;
    const double pi = 3.14159265358979323846;
    const double h = 2.0 * pi / n;
    double sum = 0.0;
    int k;

    if (!(t > 0.0) || n < 2 || (n % 2) != 0)
        return NAN;
    for (k = 0; k < n / 2; ++k) {
        const double th = (k + 0.5) * h;
        const double sa = sin(alpha * th), ca = cos(alpha * th);
        const double cot = ca / sa;
        /* w = z t (dimensionless), dw = z'(theta) t */
        const double complex w = n * (mu * th * cot - sigma + I * nu * th);
        const double complex dw =
            n * (mu * (cot - alpha * th / (sa * sa)) + I * nu);
        /* e^{zt} F(z) z'(theta) = e^w F(w/t) dw/t */
        sum += cimag(cexp(w) * step_transform(f, w / t) * dw / t);
    }
    return 2.0 * sum / n;
}

double pfh_ref_step_n(const pf_params *p, double t, int n)
{
    const step_tf f = {p, 0.0};
    return talbot(&f, t, n);
}

double pfh_ref_step(const pf_params *p, double t)
{
    return pfh_ref_step_n(p, t, PFH_REF_TALBOT_N);
}

double complex pfh_ref_line(const pf_effects *fx, double complex s)
{
    double complex l = 1.0;
    if (fx == NULL)
        return l;
    if (fx->lag > 0.0)
        l /= 1.0 + fx->lag * s;
    if (fx->dead_time > 0.0)
        l *= cexp(-fx->dead_time * s);
    return l;
}

double pfh_ref_step_fx(const pf_params *p, const pf_effects *fx, double t)
{
    /* The lag is a pole on the negative real axis, inside the contour; the
     * dead time's e^{-sT} would grow on the contour's left reaches, so it
     * is applied as what it is, a shift in time. */
    const step_tf f = {p, fx != NULL ? fx->lag : 0.0};
    double shift = fx != NULL ? fx->dead_time : 0.0;
    return talbot(&f, t - shift, PFH_REF_TALBOT_N);
}
