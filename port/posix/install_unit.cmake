# SPDX-License-Identifier: MIT
# Run by `cmake --install` (install(SCRIPT) in this directory's
# CMakeLists.txt): writes the systemd unit with the paths of the prefix the
# install goes to. That prefix is only known now: `cmake --install --prefix
# /usr` overrides the one the build was configured with, so the unit cannot
# be configured at build time. Expects UNIT_IN, UNIT_OUT, BINDIR, DOCDIR
# (relative to the prefix, or absolute) from the install(CODE) before it.
foreach(dir BINDIR DOCDIR)
  if(IS_ABSOLUTE "${${dir}}")
    set(PNEUFRAC_UNIT_${dir} "${${dir}}")
  else()
    set(PNEUFRAC_UNIT_${dir} "${CMAKE_INSTALL_PREFIX}/${${dir}}")
  endif()
endforeach()
configure_file("${UNIT_IN}" "${UNIT_OUT}" @ONLY)
