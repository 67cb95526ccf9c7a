#!/usr/bin/python3
"""Usage: scripts/clang-syntax-check.py [FILE.cpp ...]

Compiles C++ sources with clang++ -fsyntax-only, with the flags of build/release's
compile_commands.json (gcc's), before a CI run: CI's sanitizer build is clang 14, which rejects
some code gcc accepts (a lambda capturing a structured binding). Without arguments it checks
every .cpp that differs from origin/main or main (committed or not). Exits 1 on an error."""
import json
import shlex
import subprocess
import sys

database = json.load(open("build/release/compile_commands.json"))
files = sys.argv[1:]
if not files:
    changed = subprocess.run(["git", "diff", "--name-only", "main"], capture_output=True,
                             text=True, check=True).stdout.split()
    files = [f for f in changed if f.endswith(".cpp")]
failed = 0
for entry in database:
    name = entry["file"]
    if not any(name.endswith("/" + f) for f in files):
        continue
    words = [w for w in shlex.split(entry["command"]) if w != "ccache"]
    command, skip = ["clang++"], False
    for word in words[1:]:
        if skip:
            skip = False
        elif word in ("-o", "-MF", "-MT"):
            skip = True
        elif word != "-MD":
            command.append(word)
    result = subprocess.run(command + ["-fsyntax-only"], cwd=entry["directory"],
                            capture_output=True, text=True)
    print(("ok     " if result.returncode == 0 else "ERROR  ") + name)
    if result.returncode != 0:
        print(result.stderr)
        failed = 1
sys.exit(failed)
