# SPDX-License-Identifier: BSD-3-Clause
# The Python tools as one wheel, for a controller PC: dist/kinctl-<version>-
# py3-none-any.whl in the build directory holds the `kinctl` CLI and Python
# API (tools/kinctl) and the message classes `kinctl_msgs` that lcm-gen
# generates (lcmtypes/), so one `pip install` gives a working `kinctl`.
# tools/pyproject.toml is the one description of the package; the staging
# copy only adds kinctl_msgs to its packages. Built by `pip wheel` of the
# project venv without build isolation (setuptools and wheel from
# tools/requirements.txt), so the build needs no network. cmake --install
# puts the wheel in share/kinctl/python (install.cmake).
find_package(Python3 REQUIRED COMPONENTS Interpreter)
set(KINCTL_WHEEL_STAGE ${PROJECT_BINARY_DIR}/wheel-stage)
set(KINCTL_WHEEL ${PROJECT_BINARY_DIR}/dist/kinctl-${PROJECT_VERSION}-py3-none-any.whl)
file(GLOB KINCTL_WHEEL_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tools/kinctl/*.py
     ${PROJECT_SOURCE_DIR}/tools/kinctl/*.dbc)
file(READ ${PROJECT_SOURCE_DIR}/tools/pyproject.toml KINCTL_PYPROJECT)
string(REPLACE "packages = [\"kinctl\"]" "packages = [\"kinctl\", \"kinctl_msgs\"]" KINCTL_WHEEL_PYPROJECT
       "${KINCTL_PYPROJECT}")
if(NOT KINCTL_PYPROJECT MATCHES "\nversion = \"${PROJECT_VERSION}\"\n")
  message(FATAL_ERROR "kinctl: tools/pyproject.toml's version is not the project's ${PROJECT_VERSION}")
endif()
if(KINCTL_WHEEL_PYPROJECT STREQUAL KINCTL_PYPROJECT)
  message(FATAL_ERROR "kinctl: tools/pyproject.toml has no 'packages = [\"kinctl\"]' to add kinctl_msgs to")
endif()
file(WRITE ${PROJECT_BINARY_DIR}/wheel-pyproject.toml "${KINCTL_WHEEL_PYPROJECT}")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tools/pyproject.toml)
add_custom_command(
  OUTPUT ${KINCTL_WHEEL}
  COMMAND ${CMAKE_COMMAND} -E rm -rf ${KINCTL_WHEEL_STAGE} ${PROJECT_BINARY_DIR}/dist
  COMMAND ${CMAKE_COMMAND} -E make_directory ${KINCTL_WHEEL_STAGE}/kinctl
  COMMAND ${CMAKE_COMMAND} -E copy ${KINCTL_WHEEL_SOURCES} ${KINCTL_WHEEL_STAGE}/kinctl
  COMMAND ${CMAKE_COMMAND} -E copy_directory ${KINCTL_LCMTYPES_PYTHONPATH}/kinctl_msgs
          ${KINCTL_WHEEL_STAGE}/kinctl_msgs
  COMMAND ${CMAKE_COMMAND} -E copy ${PROJECT_BINARY_DIR}/wheel-pyproject.toml ${KINCTL_WHEEL_STAGE}/pyproject.toml
  COMMAND ${CMAKE_COMMAND} -E copy ${PROJECT_SOURCE_DIR}/LICENSE ${KINCTL_WHEEL_STAGE}/LICENSE
  COMMAND ${Python3_EXECUTABLE} -m pip wheel -q --no-deps --no-build-isolation --no-index
          -w ${PROJECT_BINARY_DIR}/dist ${KINCTL_WHEEL_STAGE}
  COMMAND ${CMAKE_COMMAND} -E rm -rf ${KINCTL_WHEEL_STAGE}
  DEPENDS ${KINCTL_WHEEL_SOURCES} ${PROJECT_BINARY_DIR}/wheel-pyproject.toml
          ${KINCTL_LCMTYPES_PYTHONPATH}/kinctl_msgs/__init__.py kinctl_lcmtypes_py
  COMMENT "pip wheel: dist/kinctl-${PROJECT_VERSION}-py3-none-any.whl (kinctl and kinctl_msgs)"
  VERBATIM)
add_custom_target(kinctl_wheel ALL DEPENDS ${KINCTL_WHEEL})
