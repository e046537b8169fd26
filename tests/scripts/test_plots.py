#!/usr/bin/python3
"""scripts/plots.py on a synthetic run folder (ctest: scripts_plots; skipped, exit 77, without
Debian's python3-matplotlib)."""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "plots.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import plots  # noqa: E402


def write_run(folder, frames=40, lost=(10, 11)):
    with open(os.path.join(folder, "frames.csv"), "w") as f:
        f.write("index,timestamp_s,tracked,inlier_fraction,check_agreement,rms_m,"
                "ms_preprocess,ms_tracking,ms_icp,ms_total\n")
        for i in range(frames):
            f.write("%d,%.3f,%d,0.8,0.95,0.004,3,10,6,20\n" % (i, 0.1 * i, 0 if i in lost else 1))
    with open(os.path.join(folder, "trajectory.txt"), "w") as est, \
            open(os.path.join(folder, "groundtruth.txt"), "w") as gt:
        for i in range(frames):
            est.write("%.3f %.3f 0.5 1.0 0 0 0 1\n" % (0.1 * i, 0.05 * i))
            gt.write("%.3f %.3f 0.6 1.0 0 0 0 1\n" % (0.1 * i, 0.05 * i))  # 10 cm beside
    with open(os.path.join(folder, "report.json"), "w") as f:
        json.dump({"stage_order": ["preprocess", "tracking"]}, f)
    with open(os.path.join(folder, "exploration.json"), "w") as f:
        json.dump({"metrics": [{"t": t, "coverage": t / 100.0, "objects_correct_fraction": t / 200.0}
                               for t in range(0, 60, 10)]}, f)


class Plots(unittest.TestCase):
    def test_world_frame_error_is_the_distance_to_the_truth_at_the_same_time(self):
        est = [(0.0, 0.0, 0.5, 1.0), (0.1, 0.05, 0.5, 1.0), (5.0, 0.0, 0.0, 0.0)]
        gt = [(0.1, 0.05, 0.6, 1.0), (0.0, 0.0, 0.5, 1.3)]  # unsorted on purpose
        err = plots.world_frame_error_cm(est, gt)
        self.assertAlmostEqual(err[0], 30.0, places=6)
        self.assertAlmostEqual(err[1], 10.0, places=6)
        self.assertTrue(math.isnan(err[2]), "no ground truth within 0.02 s")

    def test_lost_runs_cover_half_a_frame_either_side(self):
        self.assertEqual(plots.lost_runs(list(range(10)), [1, 1, 1, 0, 0, 1, 1, 1, 1, 0]),
                         [(2.5, 4.5), (8.5, 9.5)])
        self.assertEqual(plots.lost_runs([0, 1], [1, 1]), [])

    def test_a_run_folder_gives_every_plot(self):
        with tempfile.TemporaryDirectory() as d:
            write_run(d)
            r = subprocess.run([sys.executable, SCRIPT, d], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("tracking", "timing", "path", "exploration"):
                path = os.path.join(d, "plots", name + ".pdf")
                with open(path, "rb") as f:
                    self.assertEqual(f.read(4), b"%PDF", path)

    def test_a_folder_without_frames_csv_is_named(self):
        with tempfile.TemporaryDirectory() as d:
            r = subprocess.run([sys.executable, SCRIPT, d], capture_output=True, text=True)
            self.assertEqual(r.returncode, 2)
            self.assertIn(d + ": no frames.csv", r.stderr)


if __name__ == "__main__":
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("SKIP: python3-matplotlib is not installed (scripts/install-deps.sh installs it)")
        sys.exit(77)
    unittest.main()
