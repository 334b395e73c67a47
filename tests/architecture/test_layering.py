#!/usr/bin/env python3
"""The layering check (.ci/check-layering) passes on the tree as it is and fails, naming the file
and line, on a copy of it with a deliberately wrong include, a folder the table does not name, or
no table. Run by ctest; standalone: python3 tests/architecture/test_layering.py."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(SOURCE, '.ci', 'check-layering')


def run_checker(root):
    return subprocess.run([sys.executable, CHECKER, '--root', root], capture_output=True,
                          text=True)


class LayeringCheck(unittest.TestCase):
    def setUp(self):
        self.copy = tempfile.mkdtemp(prefix='harmonia-layering-')
        for folder in ('host', 'fallback', 'kernels', 'docs', 'examples'):
            shutil.copytree(os.path.join(SOURCE, folder), os.path.join(self.copy, folder))

    def tearDown(self):
        shutil.rmtree(self.copy)

    def append(self, path, text):
        full = os.path.join(self.copy, path)
        with open(full, encoding='utf-8') as source:
            lines = source.read().count('\n')
        with open(full, 'a', encoding='utf-8') as source:
            source.write(text)
        return lines + 1  # the line the appended text starts on

    def test_the_tree_follows_its_table(self):
        result = run_checker(SOURCE)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)

    def test_an_upward_include_is_named_with_its_file_and_line(self):
        line = self.append('host/mesh/topology.cpp', '#include "abf/abf_newton.h"\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('host/mesh/topology.cpp:%d: includes host/abf/abf_newton.h (layer abf); '
                      'layer mesh may include only mesh' % line, result.stdout)

    def test_a_backend_may_not_reach_the_backend_selection(self):
        line = self.append('fallback/cpu_backend.cpp', '#include "solve/backend_selection.h"\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('fallback/cpu_backend.cpp:%d: includes host/solve/backend_selection.h'
                      % line, result.stdout)

    def test_the_two_backends_do_not_include_each_other(self):
        self.append('kernels/vulkan_backend.cpp', '#include "fallback/cpu_backend.h"\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('kernels/vulkan_backend.cpp', result.stdout)

    def test_a_public_header_includes_only_installed_headers(self):
        self.append('host/harmonia/abf.h', '#include "abf/angle_constraints.h"\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('host/harmonia/abf.h', result.stdout)
        self.assertIn('not installed', result.stdout)

    def test_an_example_includes_public_headers_only(self):
        first = self.append('examples/unwrap_one_file.cpp', '#include <solve/backend_selection.h>\n')
        self.append('examples/unwrap_one_file.cpp', '#include <harmonia/no_such_header.h>\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('examples/unwrap_one_file.cpp:%d: includes <solve/backend_selection.h>, which is '
                      'inside harmonia' % first, result.stdout)
        self.assertIn('examples/unwrap_one_file.cpp:%d: includes <harmonia/no_such_header.h>, which is '
                      'no public header' % (first + 1), result.stdout)

    def test_a_folder_outside_the_table_is_refused(self):
        os.makedirs(os.path.join(self.copy, 'host', 'detail'))
        with open(os.path.join(self.copy, 'host', 'detail', 'helper.h'), 'w') as header:
            header.write('#pragma once\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('host/detail/helper.h: in no layer', result.stdout)

    def test_an_include_of_no_file_is_refused(self):
        self.append('host/planar/lscm.cpp', '#include "planar/no_such_header.h"\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 1)
        self.assertIn('"planar/no_such_header.h", which is no file', result.stdout)

    def test_without_its_table_the_check_stops(self):
        with open(os.path.join(self.copy, 'docs', 'architecture.md'), 'w') as document:
            document.write('# architecture\n')
        result = run_checker(self.copy)
        self.assertEqual(result.returncode, 2)
        self.assertIn('has no layering table', result.stderr)


if __name__ == '__main__':
    unittest.main()
