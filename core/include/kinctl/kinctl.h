/* SPDX-License-Identifier: BSD-3-Clause */
/* kinctl/kinctl.h - the whole core library in one include. */
#ifndef KINCTL_KINCTL_H
#define KINCTL_KINCTL_H

#include "kinctl/real.h"
#include "kinctl/status.h"
#include "kinctl/se3.h"
#include "kinctl/orient.h"
#include "kinctl/chain.h"
#include "kinctl/fk.h"
#include "kinctl/fx.h"
#include "kinctl/ik.h"
#include "kinctl/profile.h"
#include "kinctl/scurve.h"
#include "kinctl/interp.h"
#include "kinctl/path.h"
#include "kinctl/path_cart.h"
#include "kinctl/shape.h"
#include "kinctl/zone.h"
#include "kinctl/ctrl.h"
#include "kinctl/check.h"

#endif /* KINCTL_KINCTL_H */
