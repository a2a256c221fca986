"""Unit tests of the evaluation's measures on made-up trajectories (run by tests/evaluation/test_evaluation_script.cpp:
python3 -m unittest discover -s scripts/evaluation -p 'test_*.py')."""
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from evaluation import metrics  # noqa: E402


def walk(speed=(0.3, 0.0), yaw_rate=0.0, duration=10.0, dt=0.01, z=0.3, drop_at=None):
    t = np.arange(0.0, duration + dt / 2, dt)
    pos = np.stack([speed[0] * t, speed[1] * t, np.full_like(t, z)], axis=1)
    if drop_at is not None:
        pos[t >= drop_at, 2] = 0.1 * z
    rpy = np.zeros((len(t), 3))
    rpy[:, 2] = np.angle(np.exp(1j * yaw_rate * t))  # wrapped to (-pi, pi], as /base/rpy is
    return dict(time=t, pos=pos, rpy=rpy, status="complete", duration=duration)


def row_of(d, ref=None, planar=False):
    row = metrics.motion(d, planar)
    row["rms"] = 0.0 if ref is None else metrics.rms_deviation(d, ref)
    return row


class Motion(unittest.TestCase):
    def test_displacement_and_yaw(self):
        m = metrics.motion(walk(speed=(0.3, 0.4)), planar=False)
        self.assertTrue(m["stable"], m["why"])
        self.assertAlmostEqual(m["x"], 3.0)
        self.assertAlmostEqual(m["dxy"], 5.0)
        self.assertAlmostEqual(m["distance"], 5.0)
        self.assertAlmostEqual(metrics.motion(walk(speed=(0.3, 0.4)), planar=True)["distance"], 3.0)

    def test_yaw_is_unwrapped(self):
        m = metrics.motion(walk(yaw_rate=0.5), planar=False)  # 5 rad in 10 s: wraps once
        self.assertAlmostEqual(m["yaw"], 5.0, places=6)

    def test_a_fall_or_an_early_end_is_not_stable(self):
        self.assertFalse(metrics.motion(walk(drop_at=4.0), planar=False)["stable"])
        short = walk(duration=5.0)
        short["duration"] = 10.0
        self.assertIn("ended at", metrics.motion(short, planar=False)["why"])
        failed = walk()
        failed["status"] = "failed: step 3"
        self.assertFalse(metrics.motion(failed, planar=False)["stable"])


class Deviation(unittest.TestCase):
    def test_rms_of_a_constant_offset_on_another_grid(self):
        ref = walk(dt=0.001)
        run = walk(dt=0.05)
        run["pos"][:, 1] += 0.02
        self.assertAlmostEqual(metrics.rms_deviation(run, ref), 0.02, places=9)


class Verdict(unittest.TestCase):
    def setUp(self):
        self.ref_traj = walk(speed=(0.2, 0.0), dt=0.001)  # 2 m
        self.ref = row_of(self.ref_traj)

    def test_close_run_is_within(self):
        ok, why = metrics.verdict(row_of(walk(speed=(0.198, 0.0)), self.ref_traj), self.ref)
        self.assertTrue(ok, why)

    def test_each_criterion_fails_on_its_own(self):
        far = row_of(walk(speed=(0.212, 0.0)), self.ref_traj)  # 6 % further
        self.assertEqual(metrics.verdict(far, self.ref), (False, ["distance off by 6.0 %"]))
        # the same distance by another path: 0.2 m RMS sideways is 10 % of 2 m
        side = walk(speed=(0.2, 0.0))
        side["pos"][:, 1] = 0.2 * np.sign(np.sin(side["time"] * 7))
        side["pos"][-1, 1] = 0.0
        ok, why = metrics.verdict(row_of(side, self.ref_traj), self.ref)
        self.assertFalse(ok)
        self.assertTrue(any(w.startswith("RMS deviation") for w in why), why)
        turned = row_of(walk(speed=(0.2, 0.0), yaw_rate=0.031), self.ref_traj)  # 0.31 rad at the end
        ok, why = metrics.verdict(turned, self.ref)
        self.assertEqual((ok, why), (False, ["|yaw| 0.31 rad"]))

    def test_an_unstable_reference_fails_every_row(self):
        bad_ref = row_of(walk(speed=(0.2, 0.0), drop_at=5.0))
        ok, why = metrics.verdict(row_of(walk(speed=(0.2, 0.0)), self.ref_traj), bad_ref)
        self.assertFalse(ok)
        self.assertIn("the reference is not stable", why)

    def test_planar_distance_is_signed_x(self):
        back = row_of(walk(speed=(-0.2, 0.0)), planar=True)
        ok, why = metrics.verdict(back, row_of(self.ref_traj, planar=True))
        self.assertFalse(ok)
        self.assertTrue(math.isfinite(back["distance"]) and back["distance"] < 0)


if __name__ == "__main__":
    unittest.main()


class StraightWalk(unittest.TestCase):
    def test_a_straight_walk_matching_its_planar_twin_is_met(self):
        ok, why = metrics.walk_verdict(metrics.motion(walk(speed=(0.3, 0.001)), False),
                                       metrics.motion(walk(speed=(0.29, 0.0)), True))
        self.assertTrue(ok, why)

    def test_yaw_drift_and_distance_each_fail_it(self):
        planar = metrics.motion(walk(speed=(0.3, 0.0)), True)
        turning = metrics.motion(walk(speed=(0.3, 0.0), yaw_rate=0.02), False)  # 0.2 rad at the end
        self.assertAlmostEqual(turning["yaw_max"], 0.2, places=6)
        ok, why = metrics.walk_verdict(turning, planar)
        self.assertFalse(ok)
        self.assertIn("|yaw| reached 0.200 rad", why)
        drifting = metrics.motion(walk(speed=(0.3, 0.03)), False)  # 10 % sideways
        self.assertFalse(metrics.walk_verdict(drifting, planar)[0])
        self.assertIn("lateral drift 10.0 % of forward", metrics.walk_verdict(drifting, planar)[1])
        slow = metrics.motion(walk(speed=(0.2, 0.0)), False)
        self.assertIn("forward -33.3 % from the planar base's", metrics.walk_verdict(slow, planar)[1])
        self.assertIn("no stable planar-base twin", metrics.walk_verdict(slow, None)[1])
