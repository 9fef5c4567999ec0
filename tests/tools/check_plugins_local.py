#!/usr/bin/env python3
"""Every class a plugin file registers (PERIDEAL_REGISTER) must be declared
inside an anonymous namespace: two plugin files that each define, say, a
class Damage in namespace perideal break the one-definition rule, and the
linker silently keeps one of their inline member functions for both.

    check_plugins_local.py DIR...   (exit 1, naming file, line and class)
"""
import os
import re
import sys


def anonymous_depth(lines, end):
    depth = 0
    for line in lines[:end]:
        if re.match(r"\s*namespace\s*(\{\s*)?$", line):
            depth += 1
        elif re.match(r"\s*\}\s*// namespace\s*$", line):
            depth -= 1
    return depth


def check(path):
    lines = open(path, encoding="utf-8").read().split("\n")
    problems = []
    for line in lines:
        m = re.match(r"\s*PERIDEAL_REGISTER\(\s*\w+\s*,\s*(\w+)", line)
        if not m:
            continue
        name = m.group(1)
        # A class, or an alias of one (using Name = ...;).
        where = next((k for k, l in enumerate(lines)
                      if re.match(r"\s*(class|struct)\s+%s\b(?!.*;\s*$)" % name, l)
                      or re.match(r"\s*using\s+%s\s*=" % name, l)), None)
        if where is None:
            continue  # declared in a header: the core's own class
        if anonymous_depth(lines, where) <= 0:
            problems.append("%s:%d: %s is registered but not in an anonymous namespace" % (path, where + 1, name))
    return problems


problems, checked = [], 0
for top in sys.argv[1:]:
    for root, _, files in os.walk(top):
        for f in sorted(files):
            if f.endswith(".cc"):
                p = os.path.join(root, f)
                if "PERIDEAL_REGISTER(" in open(p, encoding="utf-8").read():
                    checked += 1
                    problems += check(p)
for p in problems:
    print(p)
print("%d plugin files checked, %d classes outside an anonymous namespace" % (checked, len(problems)))
sys.exit(1 if problems or checked == 0 else 0)
