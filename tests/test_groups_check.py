#!/usr/bin/env python3
"""Every test in pcbench_tests runs in some ctest group.

ctest runs the unit tests through groups of gtest filters (tests/CMakeLists.txt,
pcbench_test_group); a test suite whose name no group's filter matches is compiled and never run
(CacheMixture's tests were, from a merge until this check). Usage:
    test_groups_check.py PCBENCH_TESTS tests/CMakeLists.txt
Exits 1 and names the tests no group runs.
"""
import fnmatch
import re
import subprocess
import sys


def groups(cmake_text):
    """(positive patterns, negative patterns) of every pcbench_test_group."""
    found = []
    for flt in re.findall(r'pcbench_test_group\(\s*\S+\s+"([^"]+)"', cmake_text, re.S):
        flt = "".join(flt.split())
        positive, _, negative = flt.partition("-")
        found.append(([p for p in positive.split(":") if p], [p for p in negative.split(":") if p]))
    return found


def test_names(binary):
    listing = subprocess.run([binary, "--gtest_list_tests"], check=True, capture_output=True,
                             text=True).stdout
    suite, names = None, []
    for line in listing.splitlines():
        if not line.strip() or line.startswith("Running main()"):
            continue
        if not line.startswith(" "):
            suite = line.split("#")[0].strip()
        else:
            names.append(suite + line.split("#")[0].strip())
    return names


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    binary, cmake_file = sys.argv[1:]
    with open(cmake_file, encoding="utf-8") as f:
        filters = groups(f.read())
    names = test_names(binary)
    orphans = [
        n for n in names
        if not any(any(fnmatch.fnmatchcase(n, p) for p in pos) and
                   not any(fnmatch.fnmatchcase(n, p) for p in neg) for pos, neg in filters)
    ]
    if orphans:
        print(f"{len(orphans)} of {len(names)} tests are in no ctest group of {cmake_file}:")
        for n in orphans:
            print("  " + n)
        sys.exit(1)
    print(f"all {len(names)} tests are in a ctest group ({len(filters)} groups)")


if __name__ == "__main__":
    main()
