/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/decls.h - C linkage for a C++ program. Every public header puts
 * its declarations between KC_BEGIN_DECLS and KC_END_DECLS, so that a C++
 * translation unit that includes it calls the C library's functions by
 * their C names (tests/install/consumer builds one).
 */
#ifndef KINCTL_DECLS_H
#define KINCTL_DECLS_H

#ifdef __cplusplus
#define KC_BEGIN_DECLS extern "C" {
#define KC_END_DECLS }
#else
#define KC_BEGIN_DECLS
#define KC_END_DECLS
#endif

#endif /* KINCTL_DECLS_H */
