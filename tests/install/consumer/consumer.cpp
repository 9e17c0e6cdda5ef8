// SPDX-License-Identifier: BSD-3-Clause
// consumer.cpp - the same consumer compiled as C++: kinctl's headers give
// their declarations C linkage (kinctl/decls.h), so a C++ program links
// against the C library as it is installed.
#include "consumer.c"
