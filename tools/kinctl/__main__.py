# SPDX-License-Identifier: BSD-3-Clause
"""`python -m kinctl ...` is the `kinctl` command."""
import sys

from kinctl.cli import main

sys.exit(main())
