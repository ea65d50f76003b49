#!/usr/bin/env python3
"""Every command line in README.md and docs/*.md agrees with the program (issue 17, item 5).

Checks, for each `hedra CMD ...` written in the README's command table or in a code block:
  1. CMD exists (`hedra CMD --help` exits 0);
  2. every option the line names (`--name` or `-o`) is an option of CMD's --help;
and, for each command of the README table, that every option of its --help is named in its
table row or in a README paragraph starting "Every command", so the README hides no option.
Then it runs every code-block example whose input files exist in the repository (examples/...),
in a temporary directory, and checks exit status 0 and that every output it names was written.

Usage: doc_commands_test.py HEDRA_BINARY REPO_ROOT
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

HEDRA, ROOT = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def help_options(cmd, cache={}):
    if cmd not in cache:
        r = subprocess.run([HEDRA, cmd, "--help"], capture_output=True, text=True)
        if r.returncode != 0:
            cache[cmd] = None
        else:
            # CLI11 lists "  -o,--output TEXT   ..." : collect every -x / --name at the start.
            groups = []  # the names of one option: ["-o", "--output"]
            for line in r.stdout.splitlines():
                m = re.match(r"\s+((?:-{1,2}[\w-]+,?)+)", line)
                if m:
                    groups.append([o for o in m.group(1).split(",") if o])
            cache[cmd] = groups
    return cache[cmd]


def help_names(cmd):
    groups = help_options(cmd)
    return None if groups is None else {o for g in groups for o in g}


def options_in(text):
    # `--name`, and short options standing alone (-o); not negative numbers.
    return set(re.findall(r"(?<![\w-])(--[a-z][\w-]*|-[a-zA-Z])(?![\w-])", text))


table_rows = {}   # command -> README table row
examples = []     # (source, command line)
common = set()    # options the README names for every command at once

with open(os.path.join(ROOT, "README.md")) as f:
    for line in f:
        m = re.match(r"\|\s*`hedra (\w[\w-]*)([^`]*)`", line)
        if m:
            table_rows[m.group(1)] = line

with open(os.path.join(ROOT, "README.md")) as f:
    for paragraph in f.read().split("\n\n"):
        if paragraph.startswith("Every command"):
            common |= options_in(paragraph)

doc_files = [os.path.join(ROOT, "README.md")] + sorted(
    os.path.join(ROOT, "docs", n) for n in os.listdir(os.path.join(ROOT, "docs")) if n.endswith(".md"))
for path in doc_files:
    in_block, pending = False, ""
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if line.lstrip().startswith("```"):
                in_block, pending = not in_block, ""
                continue
            if not in_block:
                continue
            text = re.sub(r"\s+#.*$", "", line.strip())  # a trailing comment
            if not pending:
                text = re.sub(r"^(\$ )?(\./)?(build/)?", "", text)
            text = pending + text
            if text.endswith("\\"):
                pending = text[:-1] + " "
                continue
            pending = ""
            if re.match(r"hedra \w", text):
                examples.append((f"{os.path.relpath(path, ROOT)}:{number}", text.strip()))

# 1 + 2: commands and options named anywhere exist.
for cmd, row in table_rows.items():
    opts = help_names(cmd)
    if opts is None:
        fail(f"README table: `hedra {cmd}` is not a command")
        continue
    synopsis = re.match(r"\|\s*`([^`]*)`", row).group(1)
    for o in options_in(synopsis):
        if o not in opts:
            fail(f"README table: `hedra {cmd}` has no option {o}")
    # 3: the README row names every option of the command (help and aliases excepted).
    named = options_in(row) | common
    for group in help_options(cmd):
        if "--help" in group or named & set(group):
            continue
        fail(f"README table: `hedra {cmd}` does not mention its option {'/'.join(group)}")

for where, text in examples:
    words = shlex.split(text)
    cmd = words[1]
    opts = help_names(cmd)
    if opts is None:
        fail(f"{where}: `hedra {cmd}` is not a command")
        continue
    for o in options_in(text):
        if o not in opts:
            fail(f"{where}: `hedra {cmd}` has no option {o}")

# 4: run the examples whose inputs are in the repository.
ran = 0
for where, text in examples:
    words = shlex.split(text)
    inputs = [w for w in words[2:] if w.startswith("examples/")]
    if not inputs or not all(os.path.exists(os.path.join(ROOT, w)) for w in inputs):
        continue
    with tempfile.TemporaryDirectory() as tmp:
        args = [HEDRA] + [os.path.join(ROOT, w) if w.startswith("examples/") else w for w in words[1:]]
        r = subprocess.run(args, cwd=tmp, capture_output=True, text=True, timeout=600)
        ran += 1
        if r.returncode != 0:
            fail(f"{where}: `{text}` exited {r.returncode}: {r.stderr.strip()[:300]}")
            continue
        outs = [words[i + 1] for i, w in enumerate(words[:-1]) if w in ("-o", "--json", "--svg", "--output")]
        for o in outs:
            if not os.path.exists(os.path.join(tmp, o)):
                fail(f"{where}: `{text}` did not write {o}")

print(f"{len(table_rows)} README commands, {len(examples)} examples checked, {ran} run")
if not table_rows or not examples or ran == 0:
    fail("found nothing to check: the parser no longer matches the docs")
sys.exit(1 if failures else 0)
