"""Unit tests of the evaluation's plan: its cases are the scene files under models/scenes/evaluation/
(run by tests/evaluation/test_evaluation_script.cpp)."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from evaluation import plan  # noqa: E402


class Cases(unittest.TestCase):
    def test_every_named_case_has_its_scene_file_and_keeps_the_defaults(self):
        cases = plan.all_cases()
        self.assertEqual([c["id"] for c in cases][:len(plan.CASES)], list(plan.CASES))
        for c in cases:
            plan.check_defaults(c)  # raises on a tuning key
            self.assertNotIn("duration", c["scene"], c["id"])
            self.assertTrue(os.path.isabs(c["files"][0]), c["id"])

    def test_base_and_ground_come_from_the_scene(self):
        by_id = {c["id"]: c for c in plan.all_cases()}
        self.assertEqual((by_id["quadruped_trot_flat"]["base"], by_id["quadruped_trot_flat"]["ground"]), ("floating", "rigid"))
        self.assertEqual((by_id["quadruped_trot_sand"]["base"], by_id["quadruped_trot_sand"]["ground"]), ("planar", "sand"))
        self.assertEqual(by_id["robosimian_walk_sand"]["ground"], "sand")
        self.assertEqual(by_id["a1_trot_flat"]["ground"], "rigid")  # the default contact model is the cone

    def test_paths_resolve_next_to_the_scene_file_and_absent_files_are_named(self):
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "x_walk.json")
            with open(path, "w") as f:
                json.dump({"robot": {"urdf": "robot.urdf"}, "contacts": {"model": {"type": "rbf", "file": "sand"}}}, f)
            case = plan.load_case(path)
            self.assertEqual(case["files"], [os.path.join(folder, "robot.urdf"), os.path.join(folder, "sand")])
            self.assertEqual((case["robot"], case["base"], case["ground"]), ("x", "floating", "sand"))
            self.assertIn(os.path.join(folder, "robot.urdf"), plan.missing(case))

    def test_a_tuning_key_in_a_case_is_refused(self):
        case = dict(id="tuned", scene={"controller": {"kd": 3}})
        with self.assertRaisesRegex(ValueError, "controller.kd"):
            plan.check_defaults(case)


class Runs(unittest.TestCase):
    def test_every_case_variant_method_and_dt_once_with_the_scene_file(self):
        case = plan.all_cases()[0]
        runs = plan.runs([case], lambda c: {"kd 3": ["controller.kd=3"]}, ["ne-pgm"], [0.001, 0.05])
        self.assertEqual([r["key"] for r in runs], [f"{case['id']}/default/ne-pgm_dt001ms", f"{case['id']}/default/ne-pgm_dt050ms",
                                                   f"{case['id']}/kd-3/ne-pgm_dt001ms", f"{case['id']}/kd-3/ne-pgm_dt050ms"])
        cmd = plan.command("nmdp", case["path"], runs[3], ["integrator.order=2"], 0.2, "out.h5")
        self.assertEqual(cmd[:3], ["nmdp", "simulate", case["path"]])
        sets = [cmd[i + 1] for i, x in enumerate(cmd) if x == "--set"]
        self.assertEqual(sets, ["integrator.order=2", "controller.kd=3", "integrator.method=ne-pgm", "integrator.dt=0.05",
                                "duration=0.2"])

    def test_two_variants_with_one_file_name_are_refused(self):
        with self.assertRaisesRegex(ValueError, "share a file name"):
            plan.runs(plan.all_cases()[:1], lambda c: {"kd 3": [], "kd-3": []}, ["ne-pgm"], [0.01])


if __name__ == "__main__":
    unittest.main()
