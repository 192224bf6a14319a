/* SPDX-License-Identifier: MIT */
/* The generated headers' objects as a C++ translation unit compiled them
 * (export_cxx.cpp), for test_export. */
#ifndef EXPORT_CXX_H
#define EXPORT_CXX_H

#include "pneufrac/pf_controller.h"

#ifdef __cplusplus
extern "C" {
#endif

const pf_ctrl_coeffs_q15 *cxx_example6_q15(void);
const pf_ctrl_coeffs_f32 *cxx_example6_f32(void);
const pf_ctrl_coeffs_q15 *cxx_pid_fx_q15(void);
const pf_ctrl_coeffs_f32 *cxx_pid_fx_f32(void);
const pf_ctrl_coeffs_q15 *cxx_nozzle_fx_q15(void);

#ifdef __cplusplus
}
#endif
#endif
