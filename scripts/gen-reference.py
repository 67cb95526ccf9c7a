#!/usr/bin/env python3
"""Generates docs/reference/estimators.md, the estimator and integrand reference.

    python3 scripts/gen-reference.py build/release/pcbench            # rewrite the file
    python3 scripts/gen-reference.py build/release/pcbench --check    # exit 1 if it is stale

Its content comes from two places only: `pcbench list --json` (names, descriptions, parameters
with their types and defaults, declared workloads of the negative controls) and the leading doc
comment of each estimator's and integrand's source file (the `//` lines that open the file). Run
from anywhere; SOURCE_DIR defaults to the repository holding this script. ctest `docs.reference`
(label ci) runs the --check form.
"""

import argparse
import difflib
import json
import re
import subprocess
import sys
from pathlib import Path

OUTPUT = Path("docs/reference/estimators.md")
REGENERATE = "python3 scripts/gen-reference.py build/release/pcbench"


def leading_comment(path):
    """The `//` lines that open a file, without the `// ` prefix."""
    lines = []
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("//"):
            lines.append(line[3:] if line.startswith("// ") else line[2:])
        else:
            break
    while lines and not lines[-1].strip():
        lines.pop()
    return lines


def underscored(name):
    return name.replace("-", "_")


def estimator_files(source, entry):
    """The files whose doc blocks document an estimator: its analytic form, its scene form."""
    files = []
    name = entry["name"]
    if entry["analytic"]:
        # The family's members share resampling.h; the negative controls negative_controls.h.
        own = source / "estimators" / f"{underscored(name)}.h"
        if own.exists():
            files.append(own)
        elif name.startswith("ctl-"):
            files.append(source / "estimators" / "negative_controls.h")
        else:
            files.append(source / "estimators" / "resampling.h")
    if entry["scenes"]:
        files.append(source / "estimators" / "scene" / f"{underscored(name)}.cpp")
    for path in files:
        if not path.exists():
            sys.exit(f"gen-reference: no source file {path.relative_to(source)} for estimator "
                     f"'{name}' (teach estimator_files() in scripts/gen-reference.py where it is)")
        if not re.search(rf"(?<![\w-]){re.escape(name)}(?![\w-])",
                         "\n".join(leading_comment(path))):
            sys.exit(f"gen-reference: the doc block of {path.relative_to(source)} does not name "
                     f"estimator '{name}': start the file with a comment that describes it")
    return files


def integrand_file(source, entry):
    """The header that defines an integrand's model class (from integrands/registry.cpp)."""
    name = entry["name"]
    registry = (source / "integrands" / "registry.cpp").read_text(encoding="utf-8")
    match = re.search(rf'point_entry<(\w+)>\(\s*"{re.escape(name)}"', registry)
    candidates = []
    if match:
        cls = match.group(1)
        for header in sorted((source / "integrands").glob("*.h")):
            if re.search(rf"^(class|struct) {cls}\b", header.read_text(encoding="utf-8"), re.M):
                candidates.append(header)
    own = source / "integrands" / f"{underscored(name)}.h"
    if not candidates and own.exists():
        candidates.append(own)
    if not candidates:
        sys.exit(f"gen-reference: no source file found for integrand '{name}' (teach "
                 f"integrand_file() in scripts/gen-reference.py where it is)")
    if not leading_comment(candidates[0]):
        sys.exit(f"gen-reference: {candidates[0].relative_to(source)} has no leading doc comment")
    return candidates[0]


def sentence(text):
    """A description as a sentence: capitalised, with a full stop."""
    text = cell(text)
    text = text[:1].upper() + text[1:]
    return text if text.endswith(".") else text + "."


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def param_table(params):
    if not params:
        return ["No parameters.", ""]
    lines = ["| parameter | type | default | description |", "|---|---|---|---|"]
    for p in params:
        default = "required" if p["required"] and p["default"] in (None, "") else p["default"]
        default = "—" if default in (None, "") else f"`{cell(default)}`"
        lines.append(f"| `{p['name']}` | {cell(p['type'])} | {default} | {cell(p['description'])} |")
    return lines + [""]


def configuration_table(configurations):
    """An estimator's named configurations: parameters over its defaults."""
    if not configurations:
        return []
    lines = ["Named configurations on scenes (parameters over the defaults):", "",
             "| configuration | parameters |", "|---|---|"]
    for c in configurations:
        params = " ".join(f"`-p {k}={v}`" for k, v in c["params"].items())
        lines.append(f"| `{c['name']}` | {cell(params)} |")
    return lines + [""]


def link(source, path, up="../.."):
    rel = path.relative_to(source).as_posix()
    return f"[`{rel}`]({up}/{rel})"


def anchor(rel):
    return re.sub(r"[^a-z0-9 _-]", "", rel.lower()).replace(" ", "-")


def generate(pcbench, source):
    listing = json.loads(subprocess.run([pcbench, "list", "--json"], check=True,
                                        capture_output=True, text=True).stdout)
    doc_files = []  # in order of first mention

    def cite(path):
        if path not in doc_files:
            doc_files.append(path)
        rel = path.relative_to(source).as_posix()
        return f"{link(source, path)} ([doc block](#{anchor(rel)}))"

    out = ["# Estimator and integrand reference", "",
           "<!-- Generated by scripts/gen-reference.py: do not edit. -->",
           f"Generated by `{REGENERATE}` from `pcbench list --json` and the leading doc comment "
           "of each estimator's and integrand's source file; do not edit it by hand. ctest "
           "`docs.reference` (label ci) fails when it is not current. The guide to choosing "
           "among them is [docs/guide/running.md](../guide/running.md) (analytic) and "
           "[docs/guide/scenes.md](../guide/scenes.md) (scenes).", ""]

    estimators = listing["estimators"]
    out += ["## Estimators", "", "| estimator | analytic | scenes | description |",
            "|---|---|---|---|"]
    for e in estimators:
        biased = " **[biased]**" if e["biased"] else ""
        aliases = "".join(f" (`{a}`)" for a in e.get("aliases") or [])
        out.append(f"| [`{e['name']}`](#{anchor(e['name'])}){aliases}{biased} | "
                   f"{'yes' if e['analytic'] else '—'} | {'yes' if e['scenes'] else '—'} | "
                   f"{cell(e['description'])} |")
    out.append("")
    for e in estimators:
        out += [f"### {e['name']}", "", sentence(e["description"]), ""]
        if e.get("aliases"):
            names = ", ".join(f"`{a}`" for a in e["aliases"])
            out += [f"Also named {names}: the same estimator, runs and run ids.", ""]
        if e["biased"]:
            d = e["declared"]
            unit = "samples" if e["analytic"] else "samples per pixel"
            partners = f", against {', '.join(d['partners'])}" if d.get("partners") else ""
            params = "".join(f" -p {k}={v}" for k, v in sorted(d.get("params", {}).items()))
            out += [f"A negative control: biased on purpose. `pcbench verify -e {e['name']}` "
                    f"runs it on its declared workload, `{d['integrand']}`{params} at "
                    f"{d['samples']} {unit} × {d['replicates']} replicates{partners}, and "
                    "expects it flagged.", ""]
        if e["analytic"]:
            out += ["Parameters on analytic integrands:", ""] + param_table(e["params"])
        if e["scenes"]:
            out += ["Parameters on scenes:", ""] + param_table(e["scene_params"])
            out += configuration_table(e.get("scene_configurations") or [])
        out += ["Source: " + "; ".join(cite(p) for p in estimator_files(source, e)) + ".", ""]

    out += ["## Integrands", "", "| integrand | exact reference | tags | description |",
            "|---|---|---|---|"]
    for i in listing["integrands"]:
        tags = ", ".join(i.get("tags") or []) or "—"
        out.append(f"| [`{i['name']}`](#{anchor(i['name'])}) | {'yes' if i['exact'] else 'no'} | "
                   f"{tags} | {cell(i['description'])} |")
    out.append("")
    for i in listing["integrands"]:
        out += [f"### {i['name']}", "", sentence(i["description"]), ""]
        out += param_table(i["params"])
        out += ["Source: " + cite(integrand_file(source, i)) + ".", ""]

    scenes_header = source / "integrands" / "scenes" / "built_in_scenes.h"
    scene_file = source / "integrands" / "scenes" / "scene_file.h"
    out += ["## Scenes", "",
            "Built-in scenes (" + cite(scenes_header) + "); any other scene is a scene file, "
            "`-i path/to/scene.json` (" + cite(scene_file) + "). Every scene takes the "
            "parameters below.", "",
            "| scene | exact image | description |", "|---|---|---|"]
    for s in listing["scenes"]:
        out.append(f"| `{s['name']}` | {'yes' if s['exact'] else 'no'} | {cell(s['description'])} |")
    out.append("")
    params = {json.dumps(s["params"], sort_keys=True) for s in listing["scenes"]}
    if len(params) == 1:
        out += param_table(listing["scenes"][0]["params"])
    else:
        for s in listing["scenes"]:
            out += [f"`{s['name']}`:", ""] + param_table(s["params"])

    out += ["## Doc blocks", "",
            "The leading comment of each source file named above, as it stands in the file.", ""]
    for path in doc_files:
        rel = path.relative_to(source).as_posix()
        out += [f"### {rel}", "", "```text"] + leading_comment(path) + ["```", ""]
    return "\n".join(out).rstrip("\n") + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pcbench", help="the pcbench binary (build/release/pcbench)")
    parser.add_argument("source_dir", nargs="?", default=str(Path(__file__).resolve().parent.parent))
    parser.add_argument("--check", action="store_true",
                        help="compare with the checked-in file instead of writing it")
    args = parser.parse_args()
    source = Path(args.source_dir).resolve()
    text = generate(args.pcbench, source)
    target = source / OUTPUT
    if not args.check:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")
        print(f"wrote {OUTPUT}")
        return 0
    current = target.read_text(encoding="utf-8") if target.exists() else ""
    if current == text:
        print(f"{OUTPUT} is current")
        return 0
    diff = list(difflib.unified_diff(current.splitlines(), text.splitlines(),
                                     f"{OUTPUT} (checked in)", f"{OUTPUT} (generated)",
                                     lineterm=""))
    print("\n".join(diff[:80]))
    if len(diff) > 80:
        print(f"... ({len(diff) - 80} more diff lines)")
    print(f"\n{OUTPUT} is not current: an estimator's or integrand's parameters or doc block "
          f"changed. Regenerate it from the repository root with\n    {REGENERATE}\n"
          "and commit the result.")
    return 1


if __name__ == "__main__":
    sys.exit(main())
