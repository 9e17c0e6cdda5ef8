# SPDX-License-Identifier: BSD-3-Clause
# CPack: `cpack -G DEB` in a build directory makes kinctl_<version>_<arch>.deb
# of what `cmake --install` installs, below /usr. One package: the daemon, the
# calculator, the core library with its headers and CMake package, the
# examples and the unit; the library is static, so nothing at run time needs
# the development files.
#
# Depends comes from dpkg-shlibdeps (dpkg-dev) over the binaries: libc6,
# libconfig9, libjansson4 (kinctl-calc) and libglib2.0-0 (the statically
# linked liblcm's own dependency). find_package(kinctl) users who take
# kinctl::desc also need libconfig-dev, hence the Suggests.
set(CPACK_PACKAGE_NAME kinctl)
# License: BSD-3-Clause (LICENSE). A .deb states it in the machine-readable
# /usr/share/doc/kinctl/copyright (cmake/copyright, installed by
# install.cmake), with LCM's LGPL-2.1 for the statically linked liblcm.
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_PACKAGE_VENDOR "kinctl")
set(CPACK_PACKAGE_CONTACT "kinctl maintainers <maintainers@users.noreply.h-seed-34e0dc3b.example>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "real-time motion controller for serial robot arms")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
    "kinctl computes kinematics and trajectories in a portable C99 core and runs it at a hard fixed cycle in the "
    "daemon kinctld, which takes goals over LCM and publishes joint setpoints over LCM every cycle (a simulated arm "
    "by default). The package holds kinctld, the calculator kinctl-calc, the core library (static) with its headers "
    "and CMake package (find_package(kinctl)), example robot descriptions, the LCM message definitions with Java "
    "and Python bindings, and an example systemd unit (not enabled).")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libconfig-dev, pkg-config, cmake")
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS OFF)
set(CPACK_GENERATOR DEB)
include(CPack)
