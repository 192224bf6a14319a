# SPDX-License-Identifier: MIT
# Run by `cmake --install` (install(SCRIPT) in this directory's
# CMakeLists.txt): writes the systemd unit with the paths of the prefix the
# install goes to. That prefix is only known now: `cmake --install --prefix
# /usr` overrides the one the build was configured with, so the unit cannot
# be configured at build time. Expects, from the install(CODE) before it,
# UNIT_IN, UNIT_OUT, BINDIR and DOCDIR (relative to the prefix, or
# absolute) and PATHS (cmake/install_path.cmake).
include("${PATHS}")
pneufrac_install_path(PNEUFRAC_UNIT_BINDIR "${BINDIR}" "${CMAKE_INSTALL_PREFIX}")
pneufrac_install_path(PNEUFRAC_UNIT_DOCDIR "${DOCDIR}" "${CMAKE_INSTALL_PREFIX}")
configure_file("${UNIT_IN}" "${UNIT_OUT}" @ONLY)
