/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/fk.h - forward kinematics and the geometric Jacobian.
 *
 * Seed 000 (T = A_1 A_2 ... A_n) and seed 003 (M_0k = M_0,k-1 M_k-1,k over
 * the coded transforms; the "matrix of partial transmission ratios" is the
 * Jacobian built from those frames).
 *
 * The Jacobian is the geometric one in the base (world) frame: rows
 * vx vy vz wx wy wz, v the velocity of the tool point, one column per joint.
 * For a revolute joint with world axis z_j through p_j, column j is
 * [z_j x (p_tool - p_j); z_j]; for a prismatic joint [z_j; 0].
 *
 * q holds chain->n_joints values (rad or m). Functions return KC_E_ARG for a
 * NULL argument or a non-finite q, with outputs untouched; they do not judge
 * joint limits (see kc_chain_check_q). All are pure, allocate nothing, run in
 * time linear in the chain length, and are safe to call in the cycle and
 * from several threads on the same chain.
 */
#ifndef KINCTL_FK_H
#define KINCTL_FK_H

#include "kinctl/chain.h"
#include "kinctl/decls.h"

KC_BEGIN_DECLS

/* 6 x n Jacobian stored with a fixed leading dimension; columns beyond the
 * chain's joints are not written. */
typedef struct kc_jacobian {
    kc_real m[6][KC_MAX_JOINTS];
} kc_jacobian;

/* Tool pose in the world frame. */
kc_status kc_fk_eval(const kc_chain *chain, const kc_real *q, kc_pose *tool);

/* Every frame of the chain in the world frame: chain->n_frames poses into
 * frames, each the pose where a frame was ended (for a DH chain frames[i] is
 * base * 0T_(i+1); the base itself is a frame only if the chain began with
 * kc_chain_add_frame; the tool is not one). Also the tool pose if tool !=
 * NULL. */
kc_status kc_fk_frames(const kc_chain *chain, const kc_real *q, kc_pose *frames, kc_pose *tool);

/* Geometric Jacobian, and the tool pose if tool != NULL (it comes free). */
kc_status kc_fk_jacobian(const kc_chain *chain, const kc_real *q, kc_jacobian *jac, kc_pose *tool);

KC_END_DECLS

#endif /* KINCTL_FK_H */
