#!/usr/bin/env python3
"""The layer check catches what it is for: each test copies the production tree, makes one
forbidden change (a mutation) and expects check_layers.py to name it; the unchanged copy passes."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
CHECK = os.path.join(HERE, "check_layers.py")


class LayerCheckTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="check_layers_test.")
        for part in ("src", "include", "drivers", "docs"):
            shutil.copytree(os.path.join(ROOT, part), os.path.join(self.tmp, part))

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def run_check(self):
        return subprocess.run([sys.executable, CHECK, "--root", self.tmp], capture_output=True,
                              text=True, timeout=120)

    def add_line(self, rel, line):
        path = os.path.join(self.tmp, rel)
        self.assertTrue(os.path.isfile(path), rel)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        # After the first #include, so the mutation sits where includes sit.
        at = text.index("#include")
        with open(path, "w", encoding="utf-8") as f:
            f.write(text[:at] + line + "\n" + text[at:])

    def expect_violation(self, rel, words):
        result = self.run_check()
        self.assertEqual(result.returncode, 1, result.stdout + result.stderr)
        lines = [l for l in result.stdout.splitlines() if l.startswith(rel + ":")]
        self.assertEqual(len(lines), 1, result.stdout)
        for word in words:
            self.assertIn(word, lines[0])

    def test_the_tree_as_it_is_passes(self):
        result = self.run_check()
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)

    def test_estimator_including_the_bench(self):
        self.add_line("src/estimator/model.cpp", '#include "hrgbench/bench/sequencer/sequencer.hpp"')
        self.expect_violation("src/estimator/model.cpp", ["'estimator' may not depend on 'bench'"])

    def test_estimator_using_a_library_other_than_eigen(self):
        self.add_line("src/estimator/model.cpp", "#include <nlohmann/json.hpp>")
        self.expect_violation("src/estimator/model.cpp", ["may not use nlohmann"])

    def test_a_private_header_of_another_area(self):
        self.add_line("src/analysis/verdict.cpp", '#include "estimator/common_phase.hpp"')
        self.expect_violation("src/analysis/verdict.cpp", ["a private header of 'estimator'"])

    def test_a_public_header_including_a_private_one(self):
        self.add_line("include/hrgbench/estimator/model.hpp", '#include "estimator/common_phase.hpp"')
        self.expect_violation("include/hrgbench/estimator/model.hpp", ["private header"])

    def test_a_driver_including_the_bench(self):
        self.add_line("drivers/gyro_can/gyro_codec.cpp", '#include "hrgbench/bench/capture/capture.hpp"')
        self.expect_violation("drivers/gyro_can/gyro_codec.cpp",
                              ["'drivers/gyro_can' may not depend on 'bench'"])

    def test_the_bench_including_a_driver(self):
        self.add_line("src/bench/sequencer/sequencer.cpp", '#include "gyro_can/gyro_codec.hpp"')
        self.expect_violation("src/bench/sequencer/sequencer.cpp",
                              ["'bench' may not depend on 'drivers/gyro_can'"])

    def test_an_include_of_nothing_known(self):
        self.add_line("src/session/session_reader.cpp", '#include "hrgbench/session/nowhere.hpp"')
        self.expect_violation("src/session/session_reader.cpp", ["not a header of this tree"])

    def test_a_rule_block_that_cannot_be_read(self):
        doc = os.path.join(self.tmp, "docs", "architecture.md")
        with open(doc, encoding="utf-8") as f:
            text = f.read()
        with open(doc, "w", encoding="utf-8") as f:
            f.write(text.replace("```layers", "```text"))
        result = self.run_check()
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn("no ```layers block", result.stderr)


if __name__ == "__main__":
    unittest.main()
