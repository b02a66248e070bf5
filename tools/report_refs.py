#!/usr/bin/env python3
"""The shipped scenarios' reports against their references: a change meant to keep behaviour keeps them.

Runs `beadtwin run` on every shipped scenario (scenarios/data/*.yaml, the built-in default among them) and
`beadtwin check` on every shipped program (scenarios/data/programs/), and compares each report.json with its
reference in tests/data/reports/, leaving out what changes from run to run: the wall and stage times and
the scenario file's path, with the checkout's own path written as <repo>. The references are regenerated only in a commit that says why they changed.

  report_refs.py compare BEADTWIN [--only NAME ...]   run and compare; exit 1 on any difference
  report_refs.py update BEADTWIN [--only NAME ...]    run and write the references
  report_refs.py diff A.json B.json                   compare two report.json files as the check does

BEADTWIN is the built program (build/tools/beadtwin). A run that ends with exit code 1 (a gate failed, as
some shipped scenarios do by design) is a finished run; 2 or 3 is an error.
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
REFS = ROOT / "tests" / "data" / "reports"
# Keys whose values change from run to run, wherever they stand.
VOLATILE = {"wall_time_s", "stage_seconds", "scenario_file"}


def jobs():
    """(name, beadtwin arguments) for every shipped scenario and program."""
    out = []
    for yaml in sorted((ROOT / "scenarios" / "data").glob("*.yaml")):
        out.append((yaml.stem, ["run", str(yaml)]))
    for program in sorted((ROOT / "scenarios" / "data" / "programs").iterdir()):
        # The Fanuc macro programs are seed 002's, for its filament machining centre (its scenario says so).
        machine = ["--machine", "tma-al-550-filament", "--material", "pla"] if program.suffix == ".nc" else []
        out.append(("check-" + program.name, ["check", str(program), *machine]))
    return out


def strip(value):
    """The report without its volatile keys, with the checkout's path written as <repo>."""
    if isinstance(value, dict):
        return {k: strip(v) for k, v in value.items() if k not in VOLATILE}
    if isinstance(value, list):
        return [strip(v) for v in value]
    if isinstance(value, str):
        return value.replace(str(ROOT), "<repo>")
    return value


def differences(a, b, path="", out=None, limit=40):
    """Paths where two JSON values differ, each with both values (at most `limit`)."""
    if out is None:
        out = []
    if len(out) >= limit:
        return out
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            p = f"{path}.{k}" if path else k
            if k not in a:
                out.append(f"{p}: only in the new report")
            elif k not in b:
                out.append(f"{p}: only in the reference")
            else:
                differences(a[k], b[k], p, out, limit)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: {len(a)} items in the reference, {len(b)} in the new report")
        for i, (x, y) in enumerate(zip(a, b)):
            differences(x, y, f"{path}[{i}]", out, limit)
    elif a != b and not (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b)):
        out.append(f"{path}: {json.dumps(a)[:120]} -> {json.dumps(b)[:120]}")
    return out


def run(beadtwin, args, out_dir):
    proc = subprocess.run([beadtwin, *args, "-o", str(out_dir)], capture_output=True, text=True)
    if proc.returncode > 1:
        sys.exit(f"beadtwin {' '.join(args)} failed with exit code {proc.returncode}:\n{proc.stderr}")
    return strip(json.loads((out_dir / "report.json").read_text()))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["compare", "update", "diff"])
    parser.add_argument("paths", nargs="+")
    parser.add_argument("--only", nargs="*", default=[], help="only these scenarios or programs")
    a = parser.parse_args()
    if a.mode == "diff":
        x, y = (strip(json.loads(pathlib.Path(p).read_text())) for p in a.paths[:2])
        found = differences(x, y)
        print("\n".join(found) if found else "identical")
        return 1 if found else 0
    beadtwin = str(pathlib.Path(a.paths[0]).resolve())
    changed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in jobs():
            if a.only and name not in a.only:
                continue
            report = run(beadtwin, args, pathlib.Path(tmp) / name)
            ref = REFS / f"{name}.json"
            if a.mode == "update":
                REFS.mkdir(parents=True, exist_ok=True)
                ref.write_text(json.dumps(report, indent=1, sort_keys=True) + "\n")
                print(f"{name}: written")
                continue
            if not ref.exists():
                print(f"{name}: no reference ({ref.relative_to(ROOT)})")
                changed += 1
                continue
            found = differences(json.loads(ref.read_text()), report)
            print(f"{name}: " + ("identical" if not found else f"{len(found)}+ differences"))
            for line in found:
                print("  " + line)
            changed += bool(found)
    return 1 if changed else 0


if __name__ == "__main__":
    sys.exit(main())
