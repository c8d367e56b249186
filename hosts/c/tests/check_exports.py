#!/usr/bin/env python3
"""Checks the C ABI's shared libraries.

check_exports.py symbols LIB PREFIX   every symbol LIB defines dynamically starts with PREFIX (nm -D)
check_exports.py documented LIB HEADER...
                                      every function LIB exports is declared FR_API in a HEADER, with a
                                      comment right above its declaration or its group of declarations
"""
import re
import subprocess
import sys


def exported(library):
    out = subprocess.run(["nm", "-D", "--defined-only", library], check=True, capture_output=True, text=True).stdout
    symbols = []
    for line in out.splitlines():
        fields = line.split()
        if len(fields) == 3 and fields[1] != "A":  # version nodes
            symbols.append(fields[2].split("@")[0])
    return symbols


def documented(headers):
    """Names declared FR_API whose declaration group has a comment above it."""
    names = set()
    for header in headers:
        lines = open(header, encoding="utf-8").read().splitlines()
        commented = False  # the current group of declarations follows a comment
        in_declaration = False
        for line in lines:
            stripped = line.strip()
            if stripped.endswith("*/"):
                commented = True
            elif stripped.startswith("FR_API"):
                match = re.search(r"\b(fr_\w+)\s*\(", stripped)
                if match and commented:
                    names.add(match.group(1))
                in_declaration = not stripped.endswith(";")
            elif in_declaration:
                in_declaration = not stripped.endswith(";")
            elif stripped == "" or not stripped.startswith("FR_API"):
                if not stripped.startswith("/*") and not stripped.startswith("*"):
                    commented = False
    return names


def main():
    mode, library = sys.argv[1], sys.argv[2]
    symbols = exported(library)
    if not symbols:
        sys.exit(f"{library}: exports nothing")
    if mode == "symbols":
        prefix = sys.argv[3]
        wrong = [s for s in symbols if not s.startswith(prefix)]
        if wrong:
            sys.exit(f"{library} exports {len(wrong)} symbols outside {prefix}*: " + " ".join(sorted(wrong)[:40]))
        print(f"{library}: {len(symbols)} symbols, all {prefix}*")
    elif mode == "documented":
        names = documented(sys.argv[3:])
        missing = sorted(s for s in symbols if s not in names)
        if missing:
            sys.exit(f"{library}: exported but not documented in {' '.join(sys.argv[3:])}: " + " ".join(missing))
        print(f"{library}: all {len(symbols)} exported functions documented")
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
