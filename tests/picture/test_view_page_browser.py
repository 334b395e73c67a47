#!/usr/bin/env python3
"""The view pages of `harmonia view` in a real browser.

Headless Chromium, driven by Selenium through chromedriver, opens pages that the program made
from results of its own commands on corpus meshes, and checks what a person would see:

- the page starts (its `harmoniaView.ready` hook) with no message on the console above INFO;
- the 3D canvas draws the model: a visible triangle's centre is not the background's colour;
- moving the real mouse onto a known triangle, in the 3D view and in the UV square, shows that
  triangle's face index and chart id in the hover box, the chart id read independently from the
  page's data (decoded here) and, for an atlas, from the `g chart_N` groups of its OBJ;
- a distortion field's colour bar shows the ends the page's data holds, and the headline shows
  the atlas report's chart count;
- a layout with a turned-over triangle draws it in the flipped colour;
- two layouts on one page: both drawn, one camera (turning one turns the other).

Screenshots are kept in $HARMONIA_VIEW_ARTIFACTS (default: a folder under the system temp
directory), as the test's artifacts. Exit 77 (skipped) without Chromium, chromedriver, Selenium or
the corpus, except under CI=true, where that fails.
"""
import base64
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

SKIP = 77
IN_CI = os.environ.get("CI", "").lower() == "true"
CLI = os.environ.get("HARMONIA_CLI", "")
SHARED_DATA = os.environ.get(
    "HARMONIA_SHARED_DATA",
    os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
ARTIFACTS = os.environ.get("HARMONIA_VIEW_ARTIFACTS",
                           os.path.join(tempfile.gettempdir(), "harmonia-view-artifacts"))


def unavailable():
    """Why the test cannot run here, or None."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "python3-selenium is not installed"
    for program in ("chromium", "chromedriver"):
        if shutil.which(program) is None:
            return program + " is not installed"
    if not CLI or not os.path.exists(CLI):
        return "HARMONIA_CLI does not name the program"
    if not os.path.isdir(os.path.join(SHARED_DATA, "closed")):
        return "no corpus at " + SHARED_DATA
    return None


def page_data(path):
    """The data element of a page, parsed (independently of the page's own script)."""
    with open(path, encoding="utf-8") as page:
        text = page.read()
    match = re.search(r'<script type="application/json" id="harmonia-data">(.*?)</script>', text, re.S)
    return json.loads(match.group(1))


def typed(text, code):
    """A base64 little-endian array of struct `code` values."""
    raw = base64.b64decode(text)
    return list(struct.unpack("<%d%s" % (len(raw) // struct.calcsize(code), code), raw))


def obj_chart_of_faces(path):
    """The chart of each face from an atlas OBJ's `g chart_N` lines (triangles only)."""
    charts, current = [], None
    with open(path) as obj:
        for line in obj:
            if line.startswith("g "):
                current = int(line.split()[1].split("_")[1])
            elif line.startswith("f "):
                charts.append(current)
    return charts


def run(*arguments):
    completed = subprocess.run([CLI, *arguments], capture_output=True, text=True, timeout=600)
    if completed.returncode != 0:
        raise AssertionError("harmonia %s failed (%d): %s" % (" ".join(arguments), completed.returncode,
                                                              completed.stderr))
    return completed.stdout


class Browser:
    """Headless Chromium with WebGL on its software renderer (SwiftShader)."""

    def __init__(self):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
        options = webdriver.ChromeOptions()
        options.binary_location = shutil.which("chromium")
        for argument in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                         "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                         "--window-size=1400,900", "--disable-gpu-sandbox"):
            options.add_argument(argument)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        self.driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
        self.driver.set_script_timeout(60)

    def open(self, path):
        from selenium.webdriver.support.ui import WebDriverWait
        self.driver.get("file://" + os.path.abspath(path))
        WebDriverWait(self.driver, 60).until(
            lambda driver: driver.execute_script("return !!(window.harmoniaView && "
                                                 "(window.harmoniaView.ready || window.harmoniaView.error))"))
        error = self.hook("error")
        if error:
            raise AssertionError("the page did not start: " + str(error))

    def hook(self, expression, *arguments):
        return self.driver.execute_script("return window.harmoniaView." + expression, *arguments)

    def call(self, name, *arguments):
        return self.driver.execute_script(
            "return window.harmoniaView.%s.apply(null, arguments)" % name, *arguments)

    def console_problems(self):
        """Console entries above INFO (warnings and errors), the page's and the browser's."""
        return [entry for entry in self.driver.get_log("browser") if entry["level"] in ("WARNING", "SEVERE")]

    def pixel(self, x, y):
        """The colour at client point (x, y) of whatever canvas is there, as [r, g, b]."""
        return self.driver.execute_script("""
            const x = arguments[0], y = arguments[1];
            const canvas = document.elementFromPoint(x, y);
            if (!canvas || canvas.tagName !== 'CANVAS') return null;
            const box = canvas.getBoundingClientRect();
            const copy = document.createElement('canvas');
            copy.width = canvas.width; copy.height = canvas.height;
            const context = copy.getContext('2d');
            context.drawImage(canvas, 0, 0);
            const px = Math.floor((x - box.left) * canvas.width / box.width);
            const py = Math.floor((y - box.top) * canvas.height / box.height);
            const data = context.getImageData(px, py, 1, 1).data;
            return [data[0], data[1], data[2]];""", x, y)

    def move_mouse_to(self, x, y):
        """A real pointer move to client point (x, y)."""
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.common.actions.action_builder import ActionBuilder
        actions = ActionBuilder(self.driver)
        actions.pointer_action.move_to_location(int(round(x)), int(round(y)))
        actions.perform()
        ActionChains(self.driver).pause(0.2).perform()

    def drag(self, x, y, dx, dy):
        from selenium.webdriver.common.actions.action_builder import ActionBuilder
        actions = ActionBuilder(self.driver)
        actions.pointer_action.move_to_location(int(x), int(y)).pointer_down()
        for step in range(1, 11):
            actions.pointer_action.move_to_location(int(x + dx * step / 10), int(y + dy * step / 10))
        actions.pointer_action.pointer_up()
        actions.perform()

    def screenshot(self, name):
        os.makedirs(ARTIFACTS, exist_ok=True)
        self.driver.save_screenshot(os.path.join(ARTIFACTS, name + ".png"))

    def close(self):
        self.driver.quit()


class ViewPagesInABrowser(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="harmonia-view-")
        cls.browser = Browser()

    @classmethod
    def tearDownClass(cls):
        cls.browser.close()
        shutil.rmtree(cls.folder, ignore_errors=True)

    def file(self, name):
        return os.path.join(self.folder, name)

    def visible_faces(self, result, view, data, count=6):
        """Faces whose centre is on screen in `view` and picks back as the same face there, also a
        pixel away (the mouse moves to whole pixels)."""
        faces = []
        face_count = data["results"][result]["face_count"]
        for face in range(0, face_count, max(1, face_count // 400)):
            point = self.browser.call("faceCentreOnScreen", result, face, view)
            if not point:
                continue
            x, y = round(point["x"]), round(point["y"])
            if all(self.browser.call("pickAt", result, view, x + dx, y + dy) == face
                   for dx, dy in ((0, 0), (-1, 0), (1, 0), (0, -1), (0, 1))):
                faces.append((face, {"x": x, "y": y}))
                if len(faces) == count:
                    break
        self.assertTrue(faces, "no face of result %d is visible in the %s view" % (result, view))
        return faces

    def expect_hover_names(self, result, view, face, point, chart):
        self.browser.move_mouse_to(point["x"], point["y"])
        text = self.browser.hook("hoverText()")
        self.assertIn("face: %d" % face, text, "hovering face %d in the %s view" % (face, view))
        self.assertIn("chart: %d" % chart, text, "hovering face %d in the %s view" % (face, view))

    def expect_clean_console(self):
        self.assertEqual(self.browser.console_problems(), [])

    def test_an_atlas_page_draws_the_model_and_names_the_chart_under_the_mouse(self):
        mesh = os.path.join(SHARED_DATA, "closed", "spot.obj")
        report = json.loads(run("atlas", mesh, self.file("spot-atlas.obj"), "--view", self.file("spot.html"),
                                "--backend", "cpu", "--json"))
        data = page_data(self.file("spot.html"))
        self.browser.open(self.file("spot.html"))
        self.browser.screenshot("atlas-checker")
        result = data["results"][0]
        chart_of_face = typed(result["chart"], "i")
        self.assertEqual(chart_of_face, obj_chart_of_faces(self.file("spot-atlas.obj")))
        # The headline is the report's.
        self.assertIn(["charts", str(report["charts"])], data["headline"])
        headline = self.browser.driver.execute_script("return document.body.innerText")
        self.assertIn(str(report["charts"]), headline)
        for view in ("3d", "uv"):
            faces = self.visible_faces(0, view, data, count=3)
            if view == "3d":
                # The model's pixels are not the background's (the canvas' corner shows that).
                box = self.browser.driver.execute_script(
                    "const b = document.elementFromPoint(arguments[0], arguments[1]).getBoundingClientRect();"
                    "return [b.left, b.top];", faces[0][1]["x"], faces[0][1]["y"])
                background = self.browser.pixel(box[0] + 2, box[1] + 2)
                for face, point in faces:
                    colour = self.browser.pixel(point["x"], point["y"])
                    self.assertGreater(sum(abs(a - b) for a, b in zip(colour, background)), 12,
                                       "face %d's centre shows the background" % face)
            for face, point in faces:
                self.expect_hover_names(0, view, face, point, chart_of_face[face])
        # Each field's colour bar shows the data's ends.
        for field in result["fields"]:
            self.assertTrue(self.browser.call("setMode", field["key"]))
            bar = self.browser.call("colourBar", 0)
            self.assertAlmostEqual(bar["low"], field["low"], places=12)
            self.assertAlmostEqual(bar["high"], field["high"], places=12)
            self.browser.screenshot("atlas-" + field["key"])
        self.expect_clean_console()

    def test_a_turned_over_triangle_is_drawn_in_the_flipped_colour(self):
        # A unit square of two triangles whose second UV triangle is mirrored.
        with open(self.file("flip.obj"), "w") as obj:
            obj.write("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                      "vt 0.1 0.1\nvt 0.9 0.1\nvt 0.9 0.9\nvt 0.1 0.9\nvt 0.95 0.5\n"
                      "f 1/1 2/2 3/3\nf 1/1 3/3 4/5\n")
        run("view", self.file("flip.obj"), "--out", self.file("flip.html"))
        data = page_data(self.file("flip.html"))
        self.assertEqual(typed(data["results"][0]["flipped"], "B"), [0, 1])
        self.browser.open(self.file("flip.html"))
        self.browser.screenshot("flipped")
        point = self.browser.call("faceCentreOnScreen", 0, 1, "uv")
        self.assertIsNotNone(point)
        red, green, blue = self.browser.pixel(point["x"], point["y"])
        self.assertGreater(red, 180)   # the flipped colour, magenta
        self.assertLess(green, 90)
        self.assertGreater(blue, 120)
        self.expect_clean_console()

    def test_two_layouts_share_one_camera(self):
        mesh = os.path.join(SHARED_DATA, "disk", "camel_b.obj")
        if not os.path.exists(mesh):
            mesh = sorted(os.path.join(SHARED_DATA, "disk", name)
                          for name in os.listdir(os.path.join(SHARED_DATA, "disk")) if name.endswith(".obj"))[0]
        run("unwrap", mesh, self.file("conformal.obj"), "--method", "conformal", "--backend", "cpu",
            "--view", self.file("conformal.html"))
        run("unwrap", mesh, self.file("free.obj"), "--method", "free", "--backend", "cpu")
        run("view", self.file("conformal.obj"), self.file("free.obj"), "--mesh", mesh, "--out", self.file("both.html"))
        data = page_data(self.file("both.html"))
        self.assertEqual(len(data["results"]), 2)
        self.browser.open(self.file("both.html"))
        face, before_first = self.visible_faces(0, "3d", data, count=1)[0]
        before_second = self.browser.call("faceCentreOnScreen", 1, face, "3d")
        self.assertIsNotNone(before_second)
        # Turn the first view: the same face moves the same way in the second.
        self.browser.drag(before_first["x"], before_first["y"], 80, 30)
        after_first = self.browser.call("faceCentreOnScreen", 0, face, "3d")
        after_second = self.browser.call("faceCentreOnScreen", 1, face, "3d")
        self.assertIsNotNone(after_first)
        self.assertIsNotNone(after_second)
        moved = (after_first["x"] - before_first["x"], after_first["y"] - before_first["y"])
        self.assertGreater(abs(moved[0]) + abs(moved[1]), 5.0)
        self.assertAlmostEqual(after_second["x"] - before_second["x"], moved[0], delta=1.0)
        self.assertAlmostEqual(after_second["y"] - before_second["y"], moved[1], delta=1.0)
        self.browser.screenshot("two-layouts")
        # The single page of `unwrap --view` opens too, with its one chart.
        self.browser.open(self.file("conformal.html"))
        face, point = self.visible_faces(0, "uv", page_data(self.file("conformal.html")), count=1)[0]
        self.expect_hover_names(0, "uv", face, point, 0)
        self.expect_clean_console()


if __name__ == "__main__":
    reason = unavailable()
    if reason:
        print("test_view_page_browser: " + reason)
        sys.exit(1 if IN_CI else SKIP)
    unittest.main()
