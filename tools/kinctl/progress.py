# SPDX-License-Identifier: BSD-3-Clause
"""Progress bars (tqdm) for what takes more than a second: reading long logs,
computing and writing animations. Shown on stderr when it is a terminal,
silent otherwise (pipes, tests), unless forced with KINCTL_PROGRESS=1."""
import os


def _disable():
    force = os.environ.get("KINCTL_PROGRESS")
    if force is not None:
        return force == "0"
    return None  # tqdm: off when stderr is not a terminal


def bar(total=None, desc="", unit="it", show=True, **kw):
    """A tqdm bar (update(n), close(); a context manager); never shown when show is false."""
    from tqdm import tqdm
    return tqdm(total=total, desc=desc, unit=unit, disable=_disable() if show else True, leave=False,
                dynamic_ncols=True, **kw)


def lines_with_bar(f, name):
    """Iterates the lines of the open text file f, advancing a bar by bytes."""
    total = os.fstat(f.fileno()).st_size
    with bar(total, f"reading {os.path.basename(name)}", unit="B", unit_scale=True, unit_divisor=1024) as b:
        for line in f:
            b.update(len(line))
            yield line
