/* SPDX-License-Identifier: MIT */
/* Token pasting for the float/double templates: PF_FN(foo_) -> foo_f32. */
#ifndef PF_TMPL_H
#define PF_TMPL_H
#define PF_CAT2(a, b) a##b
#define PF_CAT(a, b) PF_CAT2(a, b)
#define PF_FN(name) PF_CAT(name, PF_SFX)
#endif
