# SPDX-License-Identifier: BSD-3-Clause
# What `cmake --install` puts where, below CMAKE_INSTALL_PREFIX (GNUInstallDirs):
#
#   bin/kinctld, bin/kinctl-calc          daemon/ and tools/ hold their own rules
#   lib/libkinctl_core_<real>.a           the core in the precision of KINCTL_REAL
#   lib/libkinctl_desc.a                  robot description files (libconfig)
#   include/kinctl/*.h                    the core's public headers and desc.h
#   lib/cmake/kinctl/                     find_package(kinctl): kinctl::core, kinctl::desc
#   share/kinctl/models/*.cfg             example robot descriptions
#   share/kinctl/lcmtypes/*.lcm           the message definitions, for other bindings
#   share/kinctl/java/kinctl_lcmtypes.jar the message classes, for lcm-spy's CLASSPATH
#   share/kinctl/python/kinctl_msgs/      the Python message package (PYTHONPATH)
#   share/kinctl/python/kinctl-*.whl      the kinctl CLI and Python API with kinctl_msgs,
#                                         to pip install on a controller PC (wheel.cmake)
#   lib/systemd/system/kinctld.service    daemon/CMakeLists.txt
#   share/doc/kinctl/                     README.md and the daemon's and models' READMEs,
#                                         LICENSE, copyright (Debian's machine-readable
#                                         format) and LCM's LGPL-2.1 text (LCM-COPYING)
#
# The core is a static library (PIC): a controller PC links it into one
# binary, and a microcontroller build takes the sources anyway. The Java jar
# and the Python package go to share/kinctl, not to /usr/share/java or
# dist-packages: both need LCM's own jar or Python module, which Debian does
# not package, so they are files to point CLASSPATH or PYTHONPATH at, not
# something the system should import by default.
include(CMakePackageConfigHelpers)

set(KINCTL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/kinctl)
set(KINCTL_SHARE_DIR ${CMAKE_INSTALL_DATADIR}/kinctl)

# kinctl::core is the precision chosen by KINCTL_REAL; its KC_REAL_FLOAT
# definition (core/CMakeLists.txt, PUBLIC) travels with the exported target,
# and a mismatch would fail at link time anyway (KC_PRECISION_SYMBOL).
set_target_properties(kinctl_core_${KINCTL_REAL} PROPERTIES EXPORT_NAME core)
set_target_properties(kinctl_desc PROPERTIES EXPORT_NAME desc)
install(TARGETS kinctl_core_${KINCTL_REAL} kinctl_desc EXPORT kinctlTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# cfgread.h and desc_tree.h are the project's own: they expose libconfig,
# which kinctl::desc links privately.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/include/kinctl ${PROJECT_SOURCE_DIR}/core/desc/include/kinctl
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h"
        PATTERN "cfgread.h" EXCLUDE PATTERN "desc_tree.h" EXCLUDE)
install(FILES ${KINCTL_GENERATED_INCLUDE}/kinctl/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/kinctl)
install(EXPORT kinctlTargets NAMESPACE kinctl:: DESTINATION ${KINCTL_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/kinctlConfig.cmake.in
  ${PROJECT_BINARY_DIR}/kinctlConfig.cmake INSTALL_DESTINATION ${KINCTL_CMAKE_DIR})
# 0.x: a minor release may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/kinctlConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/kinctlConfig.cmake ${PROJECT_BINARY_DIR}/kinctlConfigVersion.cmake
        DESTINATION ${KINCTL_CMAKE_DIR})

# Example configurations, message definitions and generated bindings.
file(GLOB KINCTL_MODEL_FILES ${PROJECT_SOURCE_DIR}/models/*.cfg)
install(FILES ${KINCTL_MODEL_FILES} DESTINATION ${KINCTL_SHARE_DIR}/models)
file(GLOB KINCTL_LCM_DEFS ${PROJECT_SOURCE_DIR}/lcmtypes/*.lcm)
install(FILES ${KINCTL_LCM_DEFS} DESTINATION ${KINCTL_SHARE_DIR}/lcmtypes)
if(KINCTL_LCMTYPES_JAR)
  install(FILES ${KINCTL_LCMTYPES_JAR} DESTINATION ${KINCTL_SHARE_DIR}/java)
endif()
install(DIRECTORY ${KINCTL_LCMTYPES_PYTHONPATH}/kinctl_msgs DESTINATION ${KINCTL_SHARE_DIR}/python
        PATTERN "__pycache__" EXCLUDE)
install(FILES ${KINCTL_WHEEL} DESTINATION ${KINCTL_SHARE_DIR}/python)

install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/daemon/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME README.kinctld.md)
install(FILES ${PROJECT_SOURCE_DIR}/models/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME README.models.md)

# The license, and LCM's: kinctld and kinctl-replay link the lcm wheel's
# static liblcm, which is LGPL-2.1, so its text travels with the binaries
# (README.md, "License", says what that asks of whoever redistributes them).
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/cmake/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
file(GLOB KINCTL_LCM_COPYING "${lcm_DIR}/../../../lcm-*.dist-info/licenses/COPYING")
if(NOT KINCTL_LCM_COPYING)
  message(FATAL_ERROR "kinctl: LCM's license text (lcm-*.dist-info/licenses/COPYING) is not beside ${lcm_DIR}")
endif()
list(GET KINCTL_LCM_COPYING 0 KINCTL_LCM_COPYING)
install(FILES ${KINCTL_LCM_COPYING} DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME LCM-COPYING)
