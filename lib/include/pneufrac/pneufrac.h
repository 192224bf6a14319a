/* SPDX-License-Identifier: MIT */
/**
 * @file pneufrac.h
 * @brief Umbrella header: fractional-order models of industrial pneumatic
 *        controllers, in double, float and Q15.
 */
#ifndef PNEUFRAC_H
#define PNEUFRAC_H

/* The one place the version is written: CMake reads these three lines
 * (project version, package files, SOVERSION), every program prints them
 * with --version, and tests/interface/test_versions.py holds the Python
 * package (pneufrac, with pneufrac-fit) to the same. */
#define PNEUFRAC_VERSION_MAJOR 0
#define PNEUFRAC_VERSION_MINOR 1
#define PNEUFRAC_VERSION_PATCH 0
#define PNEUFRAC_STR_(x) #x
#define PNEUFRAC_STR(x) PNEUFRAC_STR_(x)
#define PNEUFRAC_VERSION_STRING                                                \
    PNEUFRAC_STR(PNEUFRAC_VERSION_MAJOR) "." PNEUFRAC_STR(PNEUFRAC_VERSION_MINOR) "." \
    PNEUFRAC_STR(PNEUFRAC_VERSION_PATCH)

#include "pf_config.h"
#include "pf_status.h"
#include "pf_param_info.h"
#include "pf_fracop.h"
#include "pf_params.h"
#include "pf_effects.h"
#include "pf_controller.h"
#include "pf_bank.h"
#include "pf_q15.h"
#include "pf_runtime.h"
#include "pf_layout.h"

#endif /* PNEUFRAC_H */
