/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/desc.h - robot description files (libkinctl_desc).
 *
 * Not part of the core: this small library reads a text file with libconfig
 * (stdio, malloc) and builds a kc_chain with the core's builders. kinctld
 * and kinctl-calc both use it. Call it at start-up, never in the cycle.
 *
 * The format (libconfig syntax; models/ holds a commented example of every
 * built-in model):
 *
 *   robot = {
 *     name   = "puma560";          # required, 1-63 characters
 *     angles = "rad";              # required: "rad" or "deg", the unit of
 *                                  # every angle in the file (DH alpha and
 *                                  # theta, offsets, revolute limits and
 *                                  # their rates, base/tool rpy)
 *     base = { xyz = [0.0, 0.0, 0.0]; rpy = [0.0, 0.0, 0.0]; };  # optional
 *     tool = { xyz = [...]; rpy = [...]; };                       # optional
 *     # exactly one of dh, mdh, elements:
 *     dh = (                       # standard DH: Rz(theta) Tz(d) Tx(a) Rx(alpha)
 *       { name = "j1";             # optional joint name
 *         type = "revolute";       # "revolute" or "prismatic"
 *         a = 0.0; alpha = 90.0; d = 0.4; theta = 0.0;   # all four required
 *         limits = { q = [-160.0, 160.0]; qd = 2.0; qdd = 5.0; qddd = 50.0; };
 *       }, ... );
 *     mdh = ( ... );               # modified DH (Craig), same keys, a and
 *                                  # alpha of the previous link
 *     elements = (                 # seed 003's elementary transforms
 *       { op = "tz"; value = 0.5; },                    # constant Tz(0.5)
 *       { op = "rz"; joint = true; offset = 0.0; limits = {...}; },
 *       { op = "rz"; value = 0.0; frame = true; },      # a constant that ends a frame
 *       ... );
 *     volumes = (                  # optional: link volumes (kinctl/zone.h)
 *       { name = "upper_arm"; frame = 2; shape = "capsule";   # frame 1..m, as below
 *         from = [-0.4318, 0.0, 0.0]; to = [0.0, 0.0, 0.0]; radius = 0.08; },
 *       ... );
 *   };
 *
 * Shapes (lengths in m, in the volume's frame, or the base frame for a
 * zone; rpy in the file's angle unit, R = Rz Ry Rx as for base and tool):
 *   shape = "sphere";   xyz = [..]; radius = r;
 *   shape = "capsule";  from = [..]; to = [..]; radius = r;  (segment swept by r)
 *   shape = "cylinder"; from = [..]; to = [..]; radius = r;  (flat ends)
 *   shape = "box";      xyz = [..]; rpy = [..] (optional); half = [hx, hy, hz];
 *   shape = "frustum";  xyz; rpy (optional); bottom = [ax, ay]; top = [bx, by];
 *                       half_height = h;   (seed 003's truncated pyramid:
 *                       half sides ax, ay at z = -h, bx, by at z = +h)
 *   shape = "halfspace"; point = [..]; normal = [..];   (zones only: the
 *                       side the normal points away from is forbidden)
 * A name (optional, up to 63 characters) is what messages call it.
 *
 * Zones are read by kc_desc_load_zones from the controller section (the
 * same file kinctld reads):
 *
 *   controller = {
 *     zones = {
 *       margin = 0.02;     # m, every volume keeps this far from every zone
 *       near = 0.25;       # m, optional (kinctl/zone.h)
 *       angles = "deg";    # unit of the zones' rpy, optional (default rad)
 *       list = (
 *         { name = "table"; shape = "halfspace"; point = [0.0, 0.0, 0.0]; normal = [0.0, 0.0, 1.0]; },
 *         { name = "fence"; shape = "box"; xyz = [0.8, 0.0, 0.5]; half = [0.02, 1.0, 0.5]; }
 *       );
 *     };
 *   };
 *
 * For a revolute DH row theta is the joint's offset (theta = q + theta); for
 * a prismatic row d is. xyz in m; rpy = [about x, about y, about z] with
 * R = Rz(rpy[2]) Ry(rpy[1]) Rx(rpy[0]) (URDF's order). Every limit is
 * optional: q = [min, max] (rad/deg or m; omitted: unbounded, a continuous
 * joint), qd, qdd, qddd > 0 (per s, s^2, s^3; omitted: no limit), within
 * KC_DESC_RATE_MIN .. KC_DESC_RATE_MAX in rad or m.
 *
 * Frames: every DH or MDH row ends one frame; in elements, every joint
 * (joint = true) ends one frame and a constant ends one only with
 * frame = true. Frame k (k = 1, 2, ...) is the k-th one ended, as
 * kc_fk_frames numbers them.
 *
 * Numbers: integers and decimals both read as numbers (1 and 1.0 alike),
 * arrays [..] or lists (..) both hold vectors; libconfig itself refuses an
 * array [..] that mixes 1 and 1.5 (write 1.0). NaN and infinities
 * (1e999 overflows to inf) are rejected.
 *
 * Strictness: any key the reader does not know inside robot is an error (a
 * typo must not pass silently), as is a top-level section other than robot
 * and the reserved controller (read by kinctld). Errors name the file, the
 * line and the problem: "models/x.cfg:12: unknown joint type "revolut"
 * (expected "revolute" or "prismatic")".
 */
#ifndef KINCTL_DESC_H
#define KINCTL_DESC_H

#include "kinctl/chain.h"
#include "kinctl/decls.h"
#include "kinctl/zone.h"

KC_BEGIN_DECLS

/* The range of a rate limit (qd, qdd, qddd, in rad or m per s, s^2, s^3)
 * a description may give and kinctl-calc takes: the planners form
 * squares, cubes and ratios of the limits (kinctl/scurve.h), which stay
 * finite and nonzero within it. A jerk limit of 1e-250 underflowed into a
 * plan of no ticks, its end reached at once; limits of 1e240 overflowed
 * into positions of 1e231. */
#define KC_DESC_RATE_MIN 1e-9
#define KC_DESC_RATE_MAX 1e9

#define KC_DESC_NAME_LEN 64
#define KC_DESC_TEXT_LEN 512

/* What the file said besides the chain itself. */
typedef enum kc_desc_kind { KC_DESC_DH = 0, KC_DESC_MDH = 1, KC_DESC_ELEMENTS = 2 } kc_desc_kind;

typedef struct kc_desc_info {
    char name[KC_DESC_NAME_LEN];
    /* 1 when the file's angles are in degrees (values are converted: the
     * chain is always in rad). */
    int angles_deg;
    kc_desc_kind kind;
    int n_joints;
    /* Joint names from the file, "" where none was given. */
    char joint_names[KC_MAX_JOINTS][KC_DESC_NAME_LEN];
    /* The line of each joint's row or element in the file (0: none). */
    int joint_lines[KC_MAX_JOINTS];
    /* Link volumes read from the file (chain->volumes), and their names. */
    int n_volumes;
    char volume_names[KC_MAX_VOLUMES][KC_DESC_NAME_LEN];
} kc_desc_info;

/* Names of the zones kc_desc_load_zones read, "" where none was given. */
typedef struct kc_desc_zone_info {
    int n_zones;
    char names[KC_ZONE_MAX][KC_DESC_NAME_LEN];
} kc_desc_zone_info;

/* Where and what went wrong. line is 0 when no line applies (the file cannot
 * be opened). text is the whole message, "<file>:<line>: <problem>". */
typedef struct kc_desc_error {
    char file[KC_DESC_TEXT_LEN];
    int line;
    char problem[KC_DESC_TEXT_LEN];
    char text[2 * KC_DESC_TEXT_LEN + 32];
} kc_desc_error;

/* Reads the robot section of a description file into chain (built and
 * checked with kc_chain_check) and info (may be NULL). On error returns
 * KC_E_ARG (or KC_E_CAPACITY for too many joints or elements), fills err
 * (may be NULL) and leaves chain and info untouched. @include directives are
 * resolved relative to the file's directory. Thread-safe; not for the cycle. */
kc_status kc_desc_load_file(const char *path, kc_chain *chain, kc_desc_info *info, kc_desc_error *err);

/* The same for text in memory; name stands for the file in messages (NULL:
 * "<string>"). */
kc_status kc_desc_load_string(const char *text, const char *name, kc_chain *chain, kc_desc_info *info,
                              kc_desc_error *err);

/* Reads controller.zones of a file into set (kc_zone_set_init's margin
 * and near unless the file gives them; no zones when the file has none)
 * and info (may be NULL). Errors as kc_desc_load_file; outputs untouched on
 * error. */
kc_status kc_desc_load_zones(const char *path, kc_zone_set *set, kc_desc_zone_info *info, kc_desc_error *err);

KC_END_DECLS

#endif /* KINCTL_DESC_H */
