#!/usr/bin/env python3
"""Docs that cannot drift (ctest `docs`): checks README.md and docs/*.md
against the binary they describe.

1. The command list of `chatter --help` and README's command table agree:
   the same commands, in the same order, with the same one-line purpose and
   doc page; every such page exists and shows `chatter <command>`.
2. README links every page of docs/.
3. Every flag the docs show on a `chatter <command>` line (in a code block,
   with its continuation lines, or in inline code) is accepted by that
   command (`chatter <command> --help` lists it).
4. The key tables of docs/config.md list exactly the keys the config reader
   accepts, table by table (the reader's own list, from its "unknown key
   (expected one of: ...)" message on a probe config).

Usage: check_docs.py SOURCE_DIR CHATTER_BINARY
Prints every problem; exit status 1 if there is one."""
import pathlib
import re
import subprocess
import sys

src = pathlib.Path(sys.argv[1])
cli = sys.argv[2]
problems = []


def run(*args):
    p = subprocess.run([cli, *args], capture_output=True, text=True)
    return p.stdout + p.stderr


# ---- 1. the command list
help_text = run("--help")
commands = []  # (name, purpose, doc)
in_list = False
for line in help_text.splitlines():
    if line.startswith("Commands:"):
        in_list = True
        continue
    if in_list:
        if not line.strip():
            break
        m = re.match(r"^  (\S+)\s+(.+?) \((docs/\S+\.md)\)$", line)
        if not m:
            problems.append(f"chatter --help: cannot read the command line {line!r}")
            continue
        commands.append(m.groups())
if not commands:
    problems.append("chatter --help: no command list")

readme = (src / "README.md").read_text()
rows = re.findall(r"^\| `([a-z-]+)` \| (.+?) \| \[(docs/\S+\.md)\]\((docs/\S+\.md)\) \|$", readme, re.M)
readme_commands = [(n, p, d) for n, p, d, d2 in rows if d == d2]
if [c[0] for c in readme_commands] != [c[0] for c in commands]:
    problems.append("README's command table lists " + ", ".join(c[0] for c in readme_commands) +
                    "; chatter --help lists " + ", ".join(c[0] for c in commands))
for name, purpose, doc in commands:
    mine = [r for r in readme_commands if r[0] == name]
    if mine and (mine[0][1], mine[0][2]) != (purpose, doc):
        problems.append(f"command {name}: README says {mine[0][1]!r} ({mine[0][2]}), "
                        f"chatter --help says {purpose!r} ({doc})")
    page = src / doc
    if not page.exists():
        problems.append(f"command {name}: its page {doc} does not exist")
    elif not re.search(rf"chatter {re.escape(name)}\b", page.read_text()):
        problems.append(f"command {name}: {doc} never shows `chatter {name}`")

# ---- 2. every docs page linked from README
for page in sorted((src / "docs").glob("*.md")):
    if f"docs/{page.name}" not in readme:
        problems.append(f"README does not link docs/{page.name}")

# ---- 3. flags shown against the command's own --help
names = {c[0] for c in commands}
accepted = {}


def flags_of(command):
    if command not in accepted:
        accepted[command] = set(re.findall(r"--([a-z][a-z0-9-]*)", run(*command.split(), "--help")))
    return accepted[command]


subcommands = {}


def resolve(command, rest):
    """`chatter grind predict ...`: a command with subcommands takes the flags
    of `chatter grind predict --help`. Returns (command words, the rest)."""
    m = re.match(r"\s*([a-z]+)\b(.*)", rest)
    if not m:
        return command, rest
    key = (command, m.group(1))
    if key not in subcommands:
        p = subprocess.run([cli, command, m.group(1), "--help"], capture_output=True, text=True)
        subcommands[key] = p.returncode == 0 and p.stdout.startswith(f"Usage: chatter {command} {m.group(1)}")
    return (f"{command} {m.group(1)}", m.group(2)) if subcommands[key] else (command, rest)


start = re.compile(r"(?:^|[\s$`(])(?:build/)?chatter\s+([a-z-]+)\b(.*)")


def check_flags(where, command, text):
    for flag in re.findall(r"(?<![\w-])--([a-z][a-z0-9-]*)", text):
        if flag in ("help", "version"):
            continue
        if flag not in flags_of(command):
            problems.append(f"{where}: `chatter {command}` shows --{flag}, which `chatter {command} --help` "
                            "does not list")


for path in [src / "README.md", *sorted((src / "docs").glob("*.md"))]:
    text = path.read_text()
    lines = text.splitlines()
    fenced = False
    current = None  # the command a continuation line belongs to
    for i, line in enumerate(lines, 1):
        where = f"{path.relative_to(src)}:{i}"
        if line.lstrip().startswith("```"):
            fenced = not fenced
            current = None
            continue
        if fenced:
            m = start.search(line)
            if m and m.group(1) in names and "chatter-mpi" not in line:
                current, rest = resolve(m.group(1), m.group(2))
                check_flags(where, current, rest)
            elif current and (line.startswith((" ", "\t")) or lines[i - 2].rstrip().endswith("\\")):
                check_flags(where, current, line)
            else:
                current = None
            continue
        # Inline code: `chatter <command> ...`
        for code in re.findall(r"`([^`]*)`", line):
            m = start.search(code)
            if m and m.group(1) in names and "chatter-mpi" not in code:
                check_flags(where, *resolve(m.group(1), m.group(2)))

# ---- 4. the config key tables against the reader
import tempfile

BASE = """[process]
operation = "milling"
teeth = 2
tangential_coefficient_n_per_mm2 = 600
radial_coefficient_ratio = 0.3
radial_immersion = 0.5
[[tool.modes]]
frequency_hz = 800
damping_ratio = 0.02
stiffness_n_per_um = 8
"""
PROBE = "zq9x"  # far from every key: the message lists them all


def reader_keys(text, where):
    """The keys the reader lists for the table holding the probe key."""
    with tempfile.TemporaryDirectory() as d:
        f = pathlib.Path(d) / "probe.toml"
        f.write_text(text)
        out = run("point", str(f), "--rpm", "1000", "--depth-mm", "1")
    m = re.search(re.escape(where) + r": unknown key \(expected one of: ([^)]*)\)", out)
    if not m:
        problems.append(f"config keys: no key list for {where} in: {out.strip()[:300]}")
        return set()
    return {k.strip() for k in m.group(1).split(",")}


def with_unit_alternative(base, alt):
    """`x_n_per_m2` (or `_n_per_mm2`): the alternative's segments replace as
    many trailing segments of the key (its unit suffix)."""
    if not alt.startswith("_"):
        return alt
    n = len(alt.strip("_").split("_"))
    return "_".join(base.split("_")[:-n]) + alt


config_md = (src / "docs" / "config.md").read_text().splitlines()


def doc_keys(heading, stop_level=3):
    """Keys in the tables from `heading` to the next heading of level <= stop_level."""
    keys, inside = set(), False
    for line in config_md:
        h = re.match(r"^(#+) ", line)
        if h:
            if inside and len(h.group(1)) <= stop_level:
                break
            if line.startswith(heading):
                inside = True
            continue
        if not inside:
            continue
        m = re.match(r"^\| `(?:[a-z_0-9]+\.)?([a-z_0-9]+)`(?: \(or `([a-z_0-9]+)`\))? \|", line)
        if m:
            keys.add(m.group(1))
            if m.group(2):
                keys.add(with_unit_alternative(m.group(1), m.group(2)))
    return keys


sections = [
    ("### Top level", [(PROBE + " = 1\n" + BASE, PROBE)]),
    ("### `[process]`", [(BASE.replace("[process]\n", "[process]\n" + PROBE + " = 1\n"), "process." + PROBE)]),
    ("### `[[tool.modes]]`", [(BASE + PROBE + " = 1\n", "tool.modes[0]." + PROBE),
                              (BASE + "cantilever = { " + PROBE + " = 1 }\n", "tool.modes[0].cantilever." + PROBE)]),
    ("### Measured FRFs", [(BASE + "[[tool.frf]]\n" + PROBE + " = 1\n", "tool.frf[0]." + PROBE)]),
    ("### `[sweep]`", [(BASE + "[sweep]\n" + PROBE + " = 1\n", "sweep." + PROBE)]),
    ("### `[uncertainty]`", [(BASE + "[uncertainty]\n" + PROBE + " = 1\n", "uncertainty." + PROBE)]),
    ("### `[[positions]]`", [(BASE + "".join(f"[[positions]]\nposition_mm = {x}\n" + (PROBE + " = 1\n" if x == 0 else "") +
                                     "[[positions.tool.modes]]\nfrequency_hz = 800\ndamping_ratio = 0.02\n"
                                     "stiffness_n_per_um = 8\n" for x in (0, 10)), "positions[0]." + PROBE)]),
]
config_keys = 0
for heading, probes in sections:
    accepted = set()
    for text, where in probes:
        accepted |= reader_keys(text, where)
    documented = doc_keys(heading)
    config_keys += len(accepted)
    for k in sorted(accepted - documented):
        problems.append(f"docs/config.md {heading}: the reader accepts `{k}`, the tables do not list it")
    for k in sorted(documented - accepted):
        problems.append(f"docs/config.md {heading}: lists `{k}`, which the reader refuses")

for p in problems:
    print(p)
print(f"docs: {len(commands)} commands, {config_keys} config keys, {len(problems)} problem(s)")
sys.exit(1 if problems else 0)
