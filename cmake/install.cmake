# Installation and packaging (docs/INSTALL.md): `cmake --install build [--prefix P]` installs
#   bin/gyroflip                         the command
#   lib/<multiarch>/libgyroflip_*.a      the library's modules (static, position-independent)
#   include/gyroflip/...                 the public headers (+ device/ for the AD7739's facts)
#   lib/<multiarch>/cmake/gyroflip/      find_package(gyroflip CONFIG) -> gyroflip::gyroflip
#   lib/<multiarch>/pkgconfig/gyroflip.pc
#   lib/python3*/dist-packages/gyroflip/ the Python module (GYROFLIP_PYTHON_INSTALL_DIR)
#   share/man/man1/gyroflip*.1           the --help of the command and every subcommand
# and `cpack -G DEB` (in the build folder) makes a .deb of the same tree under /usr.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(GYROFLIP_MODULES core earth analysis sensor method rig io rigdata report workflow)
set(module_targets)
foreach(m IN LISTS GYROFLIP_MODULES)
  list(APPEND module_targets gyroflip_${m})
endforeach()

install(TARGETS gyroflip RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${module_targets} gyroflip_protocol gyroflip_lib EXPORT gyroflipTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY include/gyroflip DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp")
install(FILES firmware/drivers/ad7739/convert.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/gyroflip/device/firmware/drivers/ad7739)
# The rig protocol (firmware/protocol, the one part of the firmware the library uses: rigdata
# decodes the device's messages).
install(DIRECTORY firmware/protocol DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/gyroflip/device/firmware
        FILES_MATCHING PATTERN "*.hpp")

set(cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/gyroflip)
install(EXPORT gyroflipTargets NAMESPACE gyroflip:: DESTINATION ${cmake_dir})
configure_package_config_file(cmake/gyroflipConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/gyroflipConfig.cmake
                              INSTALL_DESTINATION ${cmake_dir})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/gyroflipConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/gyroflipConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/gyroflipConfigVersion.cmake DESTINATION ${cmake_dir})

# pkg-config: the modules in link order (a module before those it uses), then what they use.
set(GYROFLIP_PC_LIBS)
foreach(m workflow report rigdata io rig method sensor analysis earth core protocol)
  string(APPEND GYROFLIP_PC_LIBS " -lgyroflip_${m}")
endforeach()
file(RELATIVE_PATH GYROFLIP_PC_TO_PREFIX ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
configure_file(cmake/gyroflip.pc.in ${CMAKE_CURRENT_BINARY_DIR}/gyroflip.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/gyroflip.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# Man pages: the command's --help and every subcommand's (the list read from `gyroflip --help`), as
# troff (cmake/man_page.cmake); pages.stamp names them.
set(man_dir ${CMAKE_CURRENT_BINARY_DIR}/man)
add_custom_command(
  OUTPUT ${man_dir}/pages.stamp
  COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:gyroflip> -DVERSION=${PROJECT_VERSION}
          -DOUT=${man_dir} -P ${PROJECT_SOURCE_DIR}/cmake/man_page.cmake
  DEPENDS gyroflip ${PROJECT_SOURCE_DIR}/cmake/man_page.cmake
  COMMENT "Rendering the man pages from --help" VERBATIM)
add_custom_target(gyroflip_man ALL DEPENDS ${man_dir}/pages.stamp)
install(DIRECTORY ${man_dir}/ DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 FILES_MATCHING PATTERN "*.1")

# The Python module where Debian's interpreter looks for it under the prefix the install goes to
# (decided at install time, so that `cmake --install --prefix P` and cpack's /usr both get it
# right): lib/python3/dist-packages under /usr (Debian's own modules), else
# lib/python3.X/dist-packages (searched under /usr/local; PYTHONPATH elsewhere). A non-empty
# GYROFLIP_PYTHON_INSTALL_DIR (relative to the prefix) overrides it (docs/INSTALL.md).
if(GYROFLIP_PYTHON)
  set(GYROFLIP_PYTHON_INSTALL_DIR "" CACHE STRING
      "Where the Python package gyroflip is installed, relative to the prefix (empty: automatic)")
  set(py_versioned lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/dist-packages)
  install(CODE "
    set(py_dir \"${GYROFLIP_PYTHON_INSTALL_DIR}\")
    # cpack installs into <staging folder>/usr, so a prefix ending in /usr counts as /usr.
    if(py_dir STREQUAL \"\" AND CMAKE_INSTALL_PREFIX MATCHES \"(^|/)usr/?$\")
      set(py_dir lib/python3/dist-packages)
    elseif(py_dir STREQUAL \"\")
      set(py_dir ${py_versioned})
    endif()
    file(INSTALL DESTINATION \"\${CMAKE_INSTALL_PREFIX}/\${py_dir}/gyroflip\" TYPE FILE
         FILES \"$<TARGET_FILE:gyroflip_python>\")
    # The pure-Python half: the package and its allantools drop-in (every .py of the tree).
    file(INSTALL DESTINATION \"\${CMAKE_INSTALL_PREFIX}/\${py_dir}\" TYPE DIRECTORY
         FILES \"${PROJECT_SOURCE_DIR}/python/gyroflip\" FILES_MATCHING PATTERN \"*.py\")
  ")
endif()

# The .deb: one package with the command, the Python module and the development files.
# Depends: what dpkg-shlibdeps finds the binaries link (libc, libstdc++, libfmt, libhdf5, ...)
# plus the Python runtime. Recommends: the programs `gyroflip report` runs (gnuplot for the
# figures, pdfunite for report.pdf without a browser) and the -dev packages a C++ consumer's
# find_package needs (gyroflipConfig.cmake's find_dependency list); Suggests: Chromium, which
# prints the whole page as report.pdf. docs/INSTALL.md lists the same (install_deb compares).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME gyroflip)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY ${PROJECT_DESCRIPTION})
set(CPACK_PACKAGE_CONTACT "gyroflip developers <gyroflip@users.noreply.github.com>")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(GYROFLIP_PYTHON)
  # The module is built for one Python minor version (its ABI tag).
  math(EXPR py_next_minor "${Python_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}), \
python3 (<< ${Python_VERSION_MAJOR}.${py_next_minor}), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS
    "gnuplot-nox, poppler-utils, libfmt-dev, nlohmann-json3-dev, libeigen3-dev, libtomlplusplus-dev, \
libhdf5-dev, libssl-dev, liblzma-dev, libzstd-dev, libsqlite3-dev")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "chromium")
set(CPACK_STRIP_FILES ON)
include(CPack)

# Everything the install step and cpack take from the build, as one target: scripts/demo builds
# it, so that `cmake --install build` and `cpack` work after either README command
# (tests/install/check_demo_builds_install.sh checks it against the install scripts).
add_custom_target(gyroflip_installable)
add_dependencies(gyroflip_installable gyroflip gyroflip_man ${module_targets})
if(GYROFLIP_PYTHON)
  add_dependencies(gyroflip_installable gyroflip_python)
endif()
