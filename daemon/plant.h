/* SPDX-License-Identifier: BSD-3-Clause */
/* plant.h - the simulated arm kinctld drives when there is no hardware.
 *
 * Measured = commanded, or with lag_s > 0 a first-order lag per joint,
 *   q_m(k+1) = q_m(k) + a (q_c(k) - q_m(k)),  a = 1 - exp(-dt / lag_s),
 * the exact discretisation of tau q_m' = q_c - q_m for a command held over
 * each tick, qd_m then the measured position's difference over the tick
 * (without lag, qd_m is the commanded qd).
 * With the CAN output's drive feedback on (can_io.h), status_t reports the
 * drives' positions instead; the plant still gives the tick's measured
 * state. kd_plant_step is bounded arithmetic: safe for the cycle.
 */
#ifndef KINCTL_DAEMON_PLANT_H
#define KINCTL_DAEMON_PLANT_H

#include "kinctl/chain.h"

typedef struct kd_plant {
    int n;
    double dt, alpha; /* alpha = 1: no lag */
    double q[KC_MAX_JOINTS], qd[KC_MAX_JOINTS];
} kd_plant;

/* At rest at q0 (n joints). lag_s >= 0 (0: none), dt > 0. Returns 0, or
 * -1 for a bad argument. */
int kd_plant_init(kd_plant *p, int n, const kc_real *q0, double dt, double lag_s);

/* At rest at q (n joints), where the arm was found to be (can_master.h). */
void kd_plant_seat(kd_plant *p, const kc_real *q);

/* One tick with the commanded positions and velocities; fills q_meas and
 * qd_meas (n each). */
void kd_plant_step(kd_plant *p, const kc_real *q_cmd, const kc_real *qd_cmd, kc_real *q_meas, kc_real *qd_meas);

#endif
