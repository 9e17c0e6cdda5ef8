/* SPDX-License-Identifier: BSD-3-Clause */
/* plant.c - the simulated arm (plant.h). */
#include "plant.h"

#include <math.h>

int kd_plant_init(kd_plant *p, int n, const kc_real *q0, double dt, double lag_s)
{
    int j;
    if (p == NULL || q0 == NULL || n < 1 || n > KC_MAX_JOINTS || !(dt > 0.0) || !(lag_s >= 0.0) || !isfinite(lag_s))
        return -1;
    p->n = n;
    p->dt = dt;
    p->alpha = lag_s > 0.0 ? 1.0 - exp(-dt / lag_s) : 1.0;
    for (j = 0; j < n; j++) {
        p->q[j] = (double)q0[j];
        p->qd[j] = 0.0;
    }
    return 0;
}

void kd_plant_step(kd_plant *p, const kc_real *q_cmd, const kc_real *qd_cmd, kc_real *q_meas, kc_real *qd_meas)
{
    int j;
    for (j = 0; j < p->n; j++) {
        double q_prev = p->q[j];
        if (p->alpha >= 1.0) {
            p->q[j] = (double)q_cmd[j];
            p->qd[j] = (double)qd_cmd[j];
        } else {
            p->q[j] = q_prev + p->alpha * ((double)q_cmd[j] - q_prev);
            p->qd[j] = (p->q[j] - q_prev) / p->dt;
        }
        q_meas[j] = (kc_real)p->q[j];
        qd_meas[j] = (kc_real)p->qd[j];
    }
}

void kd_plant_seat(kd_plant *p, const kc_real *q)
{
    for (int j = 0; j < p->n; j++) {
        p->q[j] = (double)q[j];
        p->qd[j] = 0.0;
    }
}
