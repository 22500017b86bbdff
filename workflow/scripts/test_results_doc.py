#!/usr/bin/env python3
"""Tests of results_doc.py (run by ctest as workflow.results_doc): figures computed from a known results.csv,
a selection without runs is an error naming it, the README block is replaced in place and nothing else changes,
and the shipped templates parse."""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

try:
    import jinja2
except ImportError:  # ctest counts exit code 77 as skipped
    print("test_results_doc.py: skipped: python3-jinja2 is not installed (scripts/install_deps.sh --test installs it)")
    sys.exit(77)

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import results_doc  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))

ROWS = [
    {"dataset": "r07", "command": "run", "algorithm": "glmb2", "particles": "1", "refine": "none", "seed": "0",
     "slam.ate.se3_rmse_m": "0.5", "run_dir": "a"},
    {"dataset": "r07", "command": "run", "algorithm": "glmb2", "particles": "1", "refine": "none", "seed": "1",
     "slam.ate.se3_rmse_m": "0.7", "run_dir": "b"},
    {"dataset": "r07", "command": "run", "algorithm": "glmb2", "particles": "1", "refine": "ml", "seed": "0",
     "slam.ate.se3_rmse_m": "0.5", "refined.ate.se3_rmse_m": "0.1", "run_dir": "c"},
    {"dataset": "r07", "command": "vo", "algorithm": "vo", "particles": "0", "refine": "none", "seed": "0",
     "slam.ate.se3_rmse_m": "", "ate.se3_rmse_m": "1.25", "run_dir": "d"},
]


class ResultsSelection(unittest.TestCase):
    def setUp(self):
        self.res = results_doc.Results(ROWS)

    def test_defaults_select_the_unrefined_single_particle_runs(self):
        self.assertEqual(self.res.values("slam.ate.se3_rmse_m", dataset="r07"), [0.5, 0.7])
        self.assertAlmostEqual(self.res.mean("slam.ate.se3_rmse_m", dataset="r07"), 0.6)
        self.assertAlmostEqual(self.res.std("slam.ate.se3_rmse_m", dataset="r07"), 0.1414213562373095)

    def test_refine_seeds_and_vo_selection(self):
        self.assertEqual(self.res.values("refined.ate.se3_rmse_m", dataset="r07", refine="ml"), [0.1])
        self.assertEqual(self.res.values("slam.ate.se3_rmse_m", dataset="r07", seeds=[1]), [0.7])
        self.assertEqual(self.res.row(dataset="r07", command="vo")["ate.se3_rmse_m"], "1.25")
        self.assertEqual(self.res.seeds(dataset="r07"), [0, 1])

    def test_missing_run_or_empty_column_is_an_error_naming_it(self):
        with self.assertRaisesRegex(ValueError, "no run in results.csv matches .*'particles': 10"):
            self.res.values("slam.ate.se3_rmse_m", dataset="r07", particles=10)
        with self.assertRaisesRegex(ValueError, "column slam.ate.se3_rmse_m is empty for d"):
            self.res.values("slam.ate.se3_rmse_m", dataset="r07", command="vo")
        with self.assertRaisesRegex(ValueError, "2 runs match"):
            self.res.row(dataset="r07")


class EndToEnd(unittest.TestCase):
    def test_document_and_readme_block(self):
        with tempfile.TemporaryDirectory() as d:
            p = lambda name: os.path.join(d, name)  # noqa: E731
            with open(p("results.csv"), "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=sorted({k for r in ROWS for k in r}))
                w.writeheader()
                w.writerows(ROWS)
            with open(p("summary.md"), "w") as f:
                f.write("# Results\n\nGenerated.\n\nPreset `x`: 4 runs.\n\n## Stereo\n\n| a |\n|---|\n| 1 |\n")
            with open(p("doc.j2"), "w") as f:
                f.write("ATE {{ pm('slam.ate.se3_rmse_m', 2, dataset='r07') }}; refined vs VO "
                        "{{ pct(mean('refined.ate.se3_rmse_m', dataset='r07', refine='ml'), "
                        "mean('ate.se3_rmse_m', dataset='r07', command='vo')) }} %\n{{ summary_intro }}\n"
                        "{{ summary_tables }}\n")
            with open(p("block.j2"), "w") as f:
                f.write("mean {{ f(mean('slam.ate.se3_rmse_m', dataset='r07'), 1) }}\n")
            with open(p("README.md"), "w") as f:
                f.write("top\n<!-- results:begin -->\nold figure 9.9\n<!-- results:end -->\nbottom\n")
            args = [sys.executable, os.path.join(HERE, "results_doc.py"), "--csv", p("results.csv"), "--summary",
                    p("summary.md"), "--template", p("doc.j2"), "--readme-template", p("block.j2"), "--out",
                    p("out.md"), "--readme", p("README.md")]
            subprocess.run(args, check=True, capture_output=True)
            with open(p("out.md")) as f:
                self.assertEqual(f.read(), "ATE 0.60 ± 0.14; refined vs VO -92.0 %\nPreset `x`: 4 runs.\n"
                                           "## Stereo\n\n| a |\n|---|\n| 1 |\n")
            with open(p("README.md")) as f:
                self.assertEqual(f.read(), "top\n<!-- results:begin -->\nmean 0.6\n<!-- results:end -->\nbottom\n")

            with open(p("block.j2"), "w") as f:
                f.write("{{ mean('slam.ate.se3_rmse_m', dataset='r99') }}\n")
            r = subprocess.run(args, capture_output=True, text=True)
            self.assertEqual(r.returncode, 1)
            self.assertIn("'dataset': 'r99'", r.stderr)
            with open(p("README.md")) as f:
                self.assertIn("mean 0.6", f.read())  # a failed render leaves the README as it was


class ShippedTemplates(unittest.TestCase):
    def test_they_parse(self):
        env = jinja2.Environment()
        for name in ("results.md.j2", "readme_results.md.j2"):
            with open(os.path.join(ROOT, "workflow", "results", name)) as f:
                env.parse(f.read())

    def test_the_readme_has_the_block(self):
        with open(os.path.join(ROOT, "README.md")) as f:
            text = f.read()
        self.assertLess(text.index(results_doc.BEGIN), text.index(results_doc.END))


if __name__ == "__main__":
    unittest.main()
