# SPDX-License-Identifier: MIT
"""Runs the cross-built pneufrac library on emulated Cortex-M cores.

- images: exports coefficient sets with the host CLI and links them, with
  the cross-built library, into a Cortex-M image (and the same sets into a
  host shared object, for the host side of a comparison);
- target: loads the image into Unicorn (QEMU's Cortex-M0 or Cortex-M4
  model) and calls library functions in it as firmware would;
- host: the same calls on the host build, through ctypes;
- timing: instructions and estimated cycles of what a call executed, from
  the Arm Technical Reference Manuals' instruction timings.
"""
