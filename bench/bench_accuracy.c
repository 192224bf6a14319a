/* SPDX-License-Identifier: MIT */
/*
 * Accuracy benchmark: every case of the shared reference against the exact
 * response (tests/ref, Talbot inverse Laplace), max |error| over
 * t in [1 ms, 2 s] relative to the peak |response|, at 5, 20 and 100 kHz,
 * in double, float and Q15, with the default band and order. Prints a
 * Markdown table; never passes or fails on anything (tests do that).
 *   bench_accuracy [--quick]     --quick: 20 kHz only
 */
#include <stdio.h>
#include <string.h>

#include "pf_accuracy.h"
#include "pf_ref_csv.h"

static const double rates[] = {5000.0, 20000.0, 100000.0};

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    int i, r, a, ncase = pf_ref_case_count();
    double worst[3][3] = {{0}};

    printf("| case | fs | band (rad/s) | N | double | float | Q15 |\n");
    printf("|---|---|---|---|---|---|---|\n");
    for (r = quick ? 1 : 0; r < (quick ? 2 : 3); r++) {
        for (i = 0; i < ncase; i++) {
            pf_params p;
            pf_design_opts o, res;
            pf_acc_ref ref;
            double e[3];
            pf_ref_case(pf_ref_case_name(i), &p);
            fprintf(stderr, "[bench] %s at %.0f Hz\n", pf_ref_case_name(i), rates[r]);
            if (pf_acc_ref_make(&ref, &p, rates[r], 1e-3, 2.0) != 0)
                return 1;
            pf_design_opts_default(&o, rates[r]);
            pf_design_opts_resolve(&o, &res);
            for (a = 0; a < 3; a++) {
                e[a] = pf_acc_error(&ref, &o, (pf_acc_arith)a, NULL);
                if (e[a] > worst[r][a])
                    worst[r][a] = e[a];
            }
            printf("| %s | %.0f kHz | [%.3g, %.3g] | %d | %.4f %% | %.4f %% | %.4f %% |\n",
                   pf_ref_case_name(i), rates[r] / 1000, res.wb, res.wh, res.order,
                   100 * e[0], 100 * e[1], 100 * e[2]);
            pf_acc_ref_free(&ref);
        }
    }
    printf("\n| fs | worst double | worst float | worst Q15 |\n|---|---|---|---|\n");
    for (r = quick ? 1 : 0; r < (quick ? 2 : 3); r++)
        printf("| %.0f kHz | %.4f %% | %.4f %% | %.4f %% |\n", rates[r] / 1000,
               100 * worst[r][0], 100 * worst[r][1], 100 * worst[r][2]);
    return 0;
}
