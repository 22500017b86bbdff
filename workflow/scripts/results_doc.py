#!/usr/bin/env python3
"""Writes docs/results.md and the README's results block from the workflow's aggregate.

Usage: results_doc.py --csv OUT/results.csv --summary OUT/results.md --template workflow/results/results.md.j2
                      --readme-template workflow/results/readme_results.md.j2 --out docs/results.md
                      [--readme README.md] [--preset NAME]

The templates are Jinja2 (Debian's python3-jinja2, a dependency of snakemake). Every figure in them comes from
results.csv through the functions below; a selection that matches no run is an error naming it, so a document
never shows a figure its workflow did not produce. The README block is the text between the lines
`<!-- results:begin -->` and `<!-- results:end -->`, replaced in place.

Template functions (selection keywords: dataset, command=run, algorithm=glmb2, particles=1, refine=none, seeds):
  values(column, **sel)  -> the column's values over the selected rows (sorted by seed)
  mean(column, **sel)    -> their mean             std(column, **sel) -> their sample standard deviation
  seeds(**sel)           -> the selected rows' seeds (Monte Carlo run indices for sim)
  row(**sel)             -> the one selected row (a dict; error unless exactly one)
  f(x, d=3)              -> x with d decimals       pm(column, d=3, **sel) -> "mean ± std" with d decimals
  pct(a, b, d=1)         -> 100 (a − b) / b with a sign
"""
import argparse
import csv
import math
import os
import re
import statistics
import sys

import jinja2

DEFAULTS = {"command": "run", "algorithm": "glmb2", "particles": 1, "refine": "none"}
BEGIN, END = "<!-- results:begin -->", "<!-- results:end -->"


class Results:
    def __init__(self, rows):
        self.rows = rows

    def select(self, **sel):
        seeds = sel.pop("seeds", None)
        want = dict(DEFAULTS)
        if sel.get("command") == "vo":
            want.update(algorithm="vo", particles=0)
        want.update(sel)
        out = [r for r in self.rows if all(str(r.get(k, "")) == str(v) for k, v in want.items())]
        if seeds is not None:
            out = [r for r in out if int(r["seed"]) in set(seeds)]
        if not out:
            raise ValueError(f"results_doc: no run in results.csv matches {want}"
                             + (f" seeds {list(seeds)}" if seeds is not None else ""))
        return sorted(out, key=lambda r: int(r.get("seed") or 0))

    def values(self, column, **sel):
        rows = self.select(**sel)
        vals = []
        for r in rows:
            v = r.get(column, "")
            if v in ("", None):
                raise ValueError(f"results_doc: column {column} is empty for {r['run_dir']} (seed {r.get('seed')})")
            vals.append(float(v))
        return vals

    def mean(self, column, **sel):
        return statistics.fmean(self.values(column, **sel))

    def std(self, column, **sel):
        v = self.values(column, **sel)
        return statistics.stdev(v) if len(v) > 1 else 0.0

    def seeds(self, **sel):
        return [int(r["seed"]) for r in self.select(**sel)]

    def row(self, **sel):
        rows = self.select(**sel)
        if len(rows) != 1:
            raise ValueError(f"results_doc: {len(rows)} runs match {sel}, expected one")
        return rows[0]


def fmt(x, d=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    return f"{float(x):.{d}f}"


def render(template_path, env_globals):
    folder, name = os.path.split(os.path.abspath(template_path))
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(folder), undefined=jinja2.StrictUndefined,
                             keep_trailing_newline=True, trim_blocks=True, lstrip_blocks=True)
    env.globals.update(env_globals)
    return env.get_template(name).render()


def write_atomic(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", required=True)
    ap.add_argument("--summary", required=True, help="the aggregate's results.md (its tables are appended)")
    ap.add_argument("--template", required=True)
    ap.add_argument("--readme-template", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--readme", default=None)
    ap.add_argument("--preset", default="paper")
    a = ap.parse_args()

    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    res = Results(rows)
    with open(a.summary) as f:
        summary = f.read()
    # The aggregate's document: its title line, a provenance paragraph, then its tables (## sections).
    summary_body = re.sub(r"\A# [^\n]*\n+", "", summary)
    cut = summary_body.find("\n## ")
    summary_intro = (summary_body[:cut] if cut >= 0 else summary_body).strip().split("\n\n")[-1]  # provenance
    summary_tables = summary_body[cut + 1:].strip() if cut >= 0 else ""

    def pm(column, d=3, **sel):
        v = res.values(column, **sel)
        return fmt(statistics.fmean(v), d) + (f" ± {fmt(statistics.stdev(v), d)}" if len(v) > 1 else "")

    def pct(x, ref, d=1):
        return f"{100.0 * (x - ref) / ref:+.{d}f}"

    env_globals = {"values": res.values, "mean": res.mean, "std": res.std, "seeds": res.seeds, "row": res.row,
                   "f": fmt, "pm": pm, "pct": pct, "summary_intro": summary_intro, "summary_tables": summary_tables,
                   "preset": a.preset, "len": len, "sum": sum}
    try:
        doc = render(a.template, env_globals)
        block = render(a.readme_template, env_globals).strip("\n")
    except (ValueError, jinja2.TemplateError) as e:
        print(f"results_doc.py: {e}", file=sys.stderr)
        return 1
    write_atomic(a.out, doc)
    if a.readme:
        with open(a.readme) as f:
            readme = f.read()
        i, j = readme.find(BEGIN), readme.find(END)
        if i < 0 or j < i:
            print(f"results_doc.py: {a.readme} has no '{BEGIN}' ... '{END}' block", file=sys.stderr)
            return 1
        write_atomic(a.readme, readme[:i + len(BEGIN)] + "\n" + block + "\n" + readme[j:])
    print(f"results_doc.py: {a.out}" + (f", {a.readme} results block" if a.readme else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
