# SPDX-License-Identifier: BSD-3-Clause
# The warning set for everything kinctl writes, shared by the host build and
# the bare-metal build (mcu/); -ffp-contract=off keeps results identical
# across compilers and machines that could fuse a*b+c.
set(KINCTL_WARNINGS -Wall -Wextra -Wpedantic -Wconversion -Wdouble-promotion -Wshadow
    -Wstrict-prototypes -Wmissing-prototypes -Werror)
add_compile_options(-ffp-contract=off)
