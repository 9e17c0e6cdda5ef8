/* SPDX-License-Identifier: BSD-3-Clause */
/* fk_internal.h - the Jacobian without kc_fk_jacobian's argument checks,
 * for the solvers, which have checked the chain and q themselves (the IK
 * step runs every tick). Private to the core. */
#ifndef KINCTL_FK_INTERNAL_H
#define KINCTL_FK_INTERNAL_H

#include "kinctl/fk.h"

/* kc_fk_jacobian for non-NULL chain, jac and tool and a finite q. */
void kc_fk_jacobian_checked(const kc_chain *chain, const kc_real *q, kc_jacobian *jac, kc_pose *tool);

#endif /* KINCTL_FK_INTERNAL_H */
