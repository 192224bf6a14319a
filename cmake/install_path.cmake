# SPDX-License-Identifier: MIT
# pneufrac_install_path(OUT DIR BASE): an install directory as a consumer
# must write it. GNUInstallDirs' directories are relative to the prefix
# unless the user gave an absolute one; relative ones are written under
# BASE (a prefix, or a placeholder such as pkg-config's ${prefix}).
# Used at configure time (lib/CMakeLists.txt, the .pc file) and at install
# time (port/posix/install_unit.cmake, the systemd unit).
function(pneufrac_install_path out dir base)
  if(IS_ABSOLUTE "${dir}")
    set(${out} "${dir}" PARENT_SCOPE)
  else()
    set(${out} "${base}/${dir}" PARENT_SCOPE)
  endif()
endfunction()
