#!/usr/bin/env bash
# The demo: kinctl-calc on the built-in arms (forward kinematics, Jacobian,
# orientation conversions, a batch). Installs and builds what it needs first.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build >/dev/null
calc=build/tools/kinctl-calc

show() { printf '\n\033[1m$ %s\033[0m\n' "$*"; "$@"; }

show $calc fk --model puma560 --q 0,0.7854,-1.5708,0,0.7854,0
show $calc fk --model panda --deg --q 0,-17,0,-126,0,115,45
show $calc jacobian --model rrr3 --q 0.3,0.5,-0.8
show $calc orient --from rpy --to quat --deg 30,45,60
show $calc fk --model-file models/puma560.cfg --frames --q 0.1,0.2,0.3,0.4,0.5,0.6
printf '\n\033[1m$ kinctl-calc batch  (three requests, one of them bad)\033[0m\n'
printf '%s\n' '{"op":"fk","model":"rrr3","q":[0,0,0]}' \
              '{"op":"fk","model":"rrr3","q":[0,0]}' \
              '{"op":"orient","from":"axis-angle","to":"matrix","values":[0,0,1,1.5707963267948966]}' |
    $calc batch
