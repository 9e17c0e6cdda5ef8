// SPDX-License-Identifier: BSD-3-Clause
// kinematics_cxx.cpp - the example program compiled as C++, as a C++
// firmware would use the core: its headers declare everything with C
// linkage (kinctl/decls.h).
#include "kinematics.c"
