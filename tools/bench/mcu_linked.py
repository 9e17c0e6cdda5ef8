#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The core's code and read-only data that an image links, from its map.

Reads a GNU ld link map (-Wl,-Map) and sums the input sections .text* and
.rodata* taken from the core's archive (a path containing LIBRARY, default
libkinctl_core), per object:

    linked <object> <bytes>
    linked total <bytes>

With -ffunction-sections, -fdata-sections and --gc-sections this is what a
firmware calling the same entry points carries of the core, where the sum
over the archive's objects counts every function of every module.

With link-time optimisation (mcu/CMakeLists.txt, KINCTL_MCU_LTO) the core's
code comes out of the link's own objects (/tmp/ccXXXX.ltrans0.ltrans.o),
not the archive's: those count as the core's too, under the name "lto".
The images compile their own sources without LTO, so nothing else is in
them.
"""
import re
import sys

SECTION = re.compile(r"^ (\.(?:text|rodata)\S*)\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S+)", re.M)
LTRANS = re.compile(r"\.ltrans\d+\.ltrans\.o$")


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: mcu_linked.py MAP [LIBRARY]")
    library = sys.argv[2] if len(sys.argv) == 3 else "libkinctl_core"
    with open(sys.argv[1], encoding="utf-8") as f:
        text = f.read()
    start = text.find("Linker script and memory map")
    if start < 0:
        sys.exit("not a link map: " + sys.argv[1])
    # A long section name puts its address on the next line: join them.
    text = re.sub(r"^( \.\S+)\n\s+", r"\1 ", text[start:], flags=re.M)
    sizes = {}
    for _, _, size, obj in SECTION.findall(text):
        if library in obj:
            name = re.search(r"\(([^)]+?)(?:\.c)?\.obj\)", obj)
            key = name.group(1) if name else obj
        elif LTRANS.search(obj):
            key = "lto"
        else:
            continue
        sizes[key] = sizes.get(key, 0) + int(size, 16)
    for key in sorted(sizes):
        print("linked %s %d" % (key, sizes[key]))
    print("linked total %d" % sum(sizes.values()))


if __name__ == "__main__":
    main()
