/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/chain.h - the robot model: an open chain of elementary transforms.
 *
 * Seed 003 describes a chain as a list of coded elementary transforms: codes
 * 1-6 are rotations about x, y, z and translations along x, y, z driven by a
 * joint, codes 7-12 the same six with a constant value. Each transform ends
 * a frame O_k, so a link may carry several frames (M_0k = M_0,k-1 M_k-1,k).
 * Seed 000's standard Denavit-Hartenberg row is the special case
 * A = Rz(theta) Tz(d) Tx(a) Rx(alpha), theta = q + offset; the modified
 * (Craig) row is A = Rx(alpha) Tx(a) Rz(theta) Tz(d) with alpha and a of the
 * previous link. Both builders below produce elementary transforms, so forward
 * kinematics has one code path whatever the description.
 *
 * The tool pose is T = base * M_01 * ... * M_(m-1)m * tool.
 *
 * A kc_chain is a plain caller-owned struct of fixed size (no allocation).
 * Build it once, outside the cycle: kc_chain_init, then kc_chain_add_* calls,
 * then kc_chain_check. Reading it (kc_fk_*) is thread-safe and cycle-safe.
 * Constant transforms of zero (Tz(0), Rx(0)...) cost nothing: the builders
 * drop them while keeping the frame numbering.
 */
#ifndef KINCTL_CHAIN_H
#define KINCTL_CHAIN_H

#include <stdint.h>

#include "kinctl/decls.h"
#include "kinctl/se3.h"
#include "kinctl/shape.h"

KC_BEGIN_DECLS

/* Compile-time capacities. */
#ifndef KC_MAX_JOINTS
#define KC_MAX_JOINTS 16
#endif
/* Elementary transforms and frames of a chain: the built-in arms have at
 * most 20 and 9. A frame is a kc_pose (48 B in float) in every array of
 * frames, e.g. the one kc_zone_check fills on its stack. */
#ifndef KC_MAX_ELEMENTS
#define KC_MAX_ELEMENTS 128
#endif
#ifndef KC_MAX_FRAMES
#define KC_MAX_FRAMES 64
#endif
#define KC_MAX_VOLUMES 32

typedef enum kc_joint_type { KC_JOINT_REVOLUTE = 0, KC_JOINT_PRISMATIC = 1 } kc_joint_type;

/* The elementary transforms, numbered as seed 003's codes. */
typedef enum kc_code {
    KC_CODE_RX_JOINT = 1,
    KC_CODE_RY_JOINT = 2,
    KC_CODE_RZ_JOINT = 3,
    KC_CODE_TX_JOINT = 4,
    KC_CODE_TY_JOINT = 5,
    KC_CODE_TZ_JOINT = 6,
    KC_CODE_RX = 7,
    KC_CODE_RY = 8,
    KC_CODE_RZ = 9,
    KC_CODE_TX = 10,
    KC_CODE_TY = 11,
    KC_CODE_TZ = 12
} kc_code;

/* Limits of one joint, in rad or m and their time derivatives. Position
 * limits may be infinite (a continuous joint); the others must be positive
 * (infinity means "no limit"). */
typedef struct kc_joint_limits {
    kc_real q_min, q_max;
    kc_real qd_max, qdd_max, qddd_max;
} kc_joint_limits;

typedef struct kc_joint {
    kc_joint_type type;
    /* Added to q before it drives its transform (the DH theta or d offset). */
    kc_real offset;
    kc_joint_limits limits;
} kc_joint;

/* One elementary transform. Constant rotations keep their cosine and sine. */
typedef struct kc_element {
    uint8_t code;  /* kc_code */
    int8_t joint;  /* joint index for codes 1-6, -1 for constants */
    kc_real value; /* constant angle or length (codes 7-12) */
    kc_real c, s;  /* cos and sin of a constant rotation */
    /* +1 or -1 for a constant rotation of +-pi/2 (within rounding): FK then
     * swaps two columns instead of multiplying; 0 otherwise. */
    int8_t quarter;
} kc_element;

/* A link volume (seed 003's volume primitive in frame O_k): a shape placed in
 * frame `frame` (0 .. n_frames-1, as kc_fk_frames numbers them), moving with
 * it. Shapes and distances: kinctl/shape.h. */
typedef struct kc_link_volume {
    int frame;
    kc_shape shape;
} kc_link_volume;

typedef struct kc_chain {
    int n_joints;
    int n_elements;
    int n_frames;
    kc_joint joints[KC_MAX_JOINTS];
    kc_element elements[KC_MAX_ELEMENTS];
    /* Frame f is the pose after the first frame_end[f] elements. */
    uint8_t frame_end[KC_MAX_FRAMES];
    kc_pose base, tool;
    /* Link volumes (kc_chain_add_volume), checked against forbidden zones. */
    int n_volumes;
    kc_link_volume volumes[KC_MAX_VOLUMES];
} kc_chain;

/* One Denavit-Hartenberg row (standard or modified, per the builder): lengths
 * in m, angles in rad. For a revolute joint theta_offset is added to q; for a
 * prismatic joint d_offset is. */
typedef struct kc_dh_row {
    kc_joint_type type;
    kc_real a, alpha, d, theta;
    kc_joint_limits limits;
} kc_dh_row;

/* Generous limits for a new joint: position unbounded, derivatives infinite. */
kc_joint_limits kc_joint_limits_default(void);

/* Empties a chain: no joints, identity base and tool. Always KC_OK for a
 * non-NULL chain. Renamed per precision so that mixing a float library with
 * a double caller fails at link time. */
#define kc_chain_init KC_PRECISION_SYMBOL(kc_chain_init)
kc_status kc_chain_init(kc_chain *chain);

/* Appends a new joint driving one elementary transform (code 1-6) and ends a
 * frame after it. offset is added to q. KC_E_CAPACITY when full, KC_E_ARG for
 * a bad code, non-finite offset or invalid limits (see kc_chain_check_limits).
 * On error the chain is unchanged. */
kc_status kc_chain_add_joint(kc_chain *chain, kc_code code, kc_real offset, const kc_joint_limits *limits);

/* Appends a constant elementary transform (code 7-12, value in rad or m)
 * without ending a frame. */
kc_status kc_chain_add_const(kc_chain *chain, kc_code code, kc_real value);

/* Ends a frame at the current end of the chain. */
kc_status kc_chain_add_frame(kc_chain *chain);

/* Seed 003's form: code 1-6 with arg the 0-based joint index (which must be
 * the next joint: joints are numbered in chain order), or code 7-12 with arg
 * the constant. Every coded transform ends a frame, as in the seed. New
 * joints get kc_joint_limits_default(). */
kc_status kc_chain_add_code(kc_chain *chain, int code, kc_real arg);

/* Appends a standard DH link A = Rz(theta) Tz(d) Tx(a) Rx(alpha) and ends a
 * frame after it: frame i is then seed 000's 0T_i. */
kc_status kc_chain_add_dh(kc_chain *chain, const kc_dh_row *row);

/* Appends a modified DH link A = Rx(alpha) Tx(a) Rz(theta) Tz(d), alpha and a
 * being those of the previous link in Craig's table, and ends a frame. */
kc_status kc_chain_add_mdh(kc_chain *chain, const kc_dh_row *row);

/* Base (world to first frame) and tool (last frame to tool point) poses;
 * KC_E_ARG if not finite or the rotation is not orthonormal. */
kc_status kc_chain_set_base(kc_chain *chain, const kc_pose *base);
kc_status kc_chain_set_tool(kc_chain *chain, const kc_pose *tool);

/* Attaches a link volume (kc_shape_check(shape, 0) must pass) to frame
 * `frame`, which must already exist. KC_E_ARG for a bad shape or frame,
 * KC_E_CAPACITY beyond KC_MAX_VOLUMES; the chain is unchanged on error. */
kc_status kc_chain_add_volume(kc_chain *chain, int frame, const kc_shape *shape);

/* Replaces the limits of joint j. */
kc_status kc_chain_set_limits(kc_chain *chain, int j, const kc_joint_limits *limits);

/* KC_OK when the limits are usable: no NaN, q_min <= q_max, derivative limits
 * positive (infinity allowed). */
kc_status kc_chain_check_limits(const kc_joint_limits *limits);

/* Validates a built chain: at least one joint, every value finite, limits
 * sane, base and tool rigid, every link volume valid on an existing frame. Call once after building. */
kc_status kc_chain_check(const kc_chain *chain);

/* KC_OK when every q[i] (n_joints values) is finite and inside its position
 * limits; KC_E_ARG for a non-finite value, KC_E_LIMIT outside a limit, and
 * then *bad_joint (if not NULL) names the first offending joint. */
kc_status kc_chain_check_q(const kc_chain *chain, const kc_real *q, int *bad_joint);

/* ---- built-in models ---- */

typedef enum kc_model {
    KC_MODEL_RRR3 = 0, /* seed 000's arm: Rz(q1) l1 up, then two links in a vertical plane */
    KC_MODEL_PLANAR2,  /* seed 001 lab 4's two-link planar arm */
    KC_MODEL_PUMA560,  /* standard DH as in vectors/fk.json, with its joint limits */
    KC_MODEL_PANDA,    /* Franka Panda, modified DH plus flange-to-tool, as in fk.json */
    KC_MODEL_RB211,    /* seed 003's RB-211 coded chain, as far as the scan allows */
    KC_MODEL_RM01,     /* seed 003's RM-01 coded chain, as far as the scan allows */
    KC_MODEL_COUNT
} kc_model;

/* Parameters of the models that take them: rrr3 uses len[0..2] as l1, l2,
 * l3 (m); planar2 uses len[0..1]. NULL or a non-positive entry selects the
 * default (rrr3: 0.4, 0.3, 0.25 as in the reference data; planar2: 0.5,
 * 0.4). Other models ignore it. */
typedef struct kc_model_params {
    kc_real len[4];
} kc_model_params;

/* Builds a built-in model into chain, with its link volumes (capsules
 * around the links, sized from the arm's published drawings where there
 * are any and assumed otherwise; see models/README.md). */
kc_status kc_chain_init_model(kc_chain *chain, kc_model model, const kc_model_params *params);

/* The model's name ("rrr3", "planar2", "puma560", "panda", "rb211",
 * "rm01"), or NULL for an unknown value. */
const char *kc_model_name(kc_model model);

/* The model with that name, or -1 (KC_E_ARG) when there is none. */
int kc_model_from_name(const char *name);

KC_END_DECLS

#endif /* KINCTL_CHAIN_H */
