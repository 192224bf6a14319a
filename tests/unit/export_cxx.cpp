// SPDX-License-Identifier: MIT
// The exported coefficient headers compiled as C++20 (g++ -std=c++20
// -pedantic): test_export compares these objects with the same headers
// compiled as C, byte for byte.
#include "pf_example6_f32.h"
#include "pf_example6_q15.h"
#include "pf_pid_fx_q15.h"
#include "pf_pid_fx_f32.h"
#include "pf_nozzle_fx_q15.h"

#include "export_cxx.h"

const pf_ctrl_coeffs_q15 *cxx_example6_q15(void) { return &pf_example6_q15; }
const pf_ctrl_coeffs_f32 *cxx_example6_f32(void) { return &pf_example6_f32; }
const pf_ctrl_coeffs_q15 *cxx_pid_fx_q15(void) { return &pf_pid_fx_q15; }
const pf_ctrl_coeffs_f32 *cxx_pid_fx_f32(void) { return &pf_pid_fx_f32; }
const pf_ctrl_coeffs_q15 *cxx_nozzle_fx_q15(void) { return &pf_nozzle_fx_q15; }
