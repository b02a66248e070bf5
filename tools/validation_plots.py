#!/usr/bin/env python3
"""The comparisons of docs/validation.md, run and drawn: runs the Validation tests of a build with
BEADTWIN_VALIDATION_OUT set, prints what each found, and draws what they compared as SVG (written here, no
plotting library needed).

  python3 tools/validation_plots.py [BUILD_DIR] [--images DIR]

BUILD_DIR: the build tree (default: build); the test program is BUILD_DIR/tests/scenarios_tests.
--images: where the pictures go (default: docs/images): validation-camera-spots.svg and
validation-layer-time.svg.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]


def read_csv(path):
    """The rows of a CSV file as dicts; lines starting with # are comments."""
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


class Figure:
    """An SVG picture holding one or more plots, written as text."""

    def __init__(self, width, height, title):
        self.w, self.h = width, height
        self.parts = [
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
            f'font-family="sans-serif" font-size="12">',
            f'<rect width="{width}" height="{height}" fill="white"/>',
            f'<text x="{width / 2}" y="20" text-anchor="middle" font-size="14">{title}</text>',
        ]

    def write(self, path):
        with open(path, "w") as f:
            f.write("\n".join(self.parts + ["</svg>"]) + "\n")


class Plot:
    """A plot with linear axes in the box (left, top, right, bottom) of a figure, pixels."""

    def __init__(self, figure, box, x_range, y_range, x_label, y_label):
        self.parts = figure.parts
        self.left, self.top, self.right, self.bottom = box
        self.x0, self.x1 = x_range
        self.y0, self.y1 = y_range
        self._axes(x_label, y_label)

    def px(self, x):
        return self.left + (x - self.x0) / (self.x1 - self.x0) * (self.right - self.left)

    def py(self, y):
        return self.bottom - (y - self.y0) / (self.y1 - self.y0) * (self.bottom - self.top)

    def _axes(self, x_label, y_label):
        l, t, r, b = self.left, self.top, self.right, self.bottom
        self.parts.append(f'<rect x="{l}" y="{t}" width="{r - l}" height="{b - t}" fill="none" stroke="black"/>')
        for x in ticks(self.x0, self.x1):
            self.parts.append(f'<line x1="{self.px(x)}" y1="{b}" x2="{self.px(x)}" y2="{b + 4}" stroke="black"/>')
            self.parts.append(f'<text x="{self.px(x)}" y="{b + 17}" text-anchor="middle">{x:g}</text>')
        for y in ticks(self.y0, self.y1):
            self.parts.append(f'<line x1="{l - 4}" y1="{self.py(y)}" x2="{l}" y2="{self.py(y)}" stroke="black"/>')
            self.parts.append(f'<text x="{l - 7}" y="{self.py(y) + 4}" text-anchor="end">{y:g}</text>')
        self.parts.append(f'<text x="{(l + r) / 2}" y="{b + 34}" text-anchor="middle">{x_label}</text>')
        self.parts.append(f'<text transform="translate({l - 48},{(t + b) / 2}) rotate(-90)" '
                          f'text-anchor="middle">{y_label}</text>')

    def line(self, xs, ys, colour, dashed=False, width=1.5):
        points = " ".join(f"{self.px(x):.1f},{self.py(y):.1f}" for x, y in zip(xs, ys))
        dash = ' stroke-dasharray="6,4"' if dashed else ""
        self.parts.append(f'<polyline points="{points}" fill="none" stroke="{colour}" '
                          f'stroke-width="{width}"{dash}/>')

    def dots(self, xs, ys, colour):
        for x, y in zip(xs, ys):
            self.parts.append(f'<circle cx="{self.px(x):.1f}" cy="{self.py(y):.1f}" r="3" fill="{colour}"/>')

    def hline(self, y, colour, text):
        self.line([self.x0, self.x1], [y, y], colour, dashed=True, width=1)
        self.parts.append(f'<text x="{self.right - 4}" y="{self.py(y) - 4}" text-anchor="end" '
                          f'fill="{colour}">{text}</text>')

    def vline(self, x, colour, text=None):
        self.line([x, x], [self.y0, self.y1], colour, dashed=True, width=1)
        if text:
            self.parts.append(f'<text transform="translate({self.px(x) - 4},{self.top + 6}) rotate(90)" '
                              f'fill="{colour}" font-size="11">{text}</text>')

    def legend(self, entries, x=None):
        """Entries (text, colour, dashed) listed from the plot's top, at x pixels (default: near its left)."""
        x = self.left + 12 if x is None else x
        for k, (text, colour, dashed) in enumerate(entries):
            y = self.top + 16 + 16 * k
            dash = ' stroke-dasharray="6,4"' if dashed else ""
            self.parts.append(f'<line x1="{x}" y1="{y - 4}" x2="{x + 24}" y2="{y - 4}" stroke="{colour}" '
                              f'stroke-width="1.5"{dash}/>')
            self.parts.append(f'<text x="{x + 30}" y="{y}">{text}</text>')


def ticks(a, b):
    """About six round tick values between a and b."""
    span = b - a
    step = 10 ** int(f"{span / 6:e}".split("e")[1])
    for m in (1, 2, 5, 10):
        if span / (step * m) <= 7:
            step *= m
            break
    first = -(-a // step) * step
    return [first + k * step for k in range(int((b - first) / step + 1e-9) + 1)]


def camera_spots_numbers(rows):
    """RMS and largest difference of the camera spots from the paper's 1-D model, per layer and overall."""
    def stats(sel):
        d = [float(r["model_c"]) - float(r["papers_1d_model_c"]) for r in sel]
        return (sum(x * x for x in d) / len(d)) ** 0.5, max(abs(x) for x in d), len(d)
    for layer in sorted({int(r["paper_layer"]) for r in rows}):
        rms, most, n = stats([r for r in rows if int(r["paper_layer"]) == layer])
        print(f"camera spot, layer {layer}: {rms:.1f} K RMS, {most:.1f} K at most ({n} samples)")
    rms, most, n = stats(rows)
    print(f"camera spots, all: {rms:.1f} K RMS, {most:.1f} K at most ({n} samples; tolerance 10 K, 15 K)")


def crossing(t, values, level):
    """The first layer time at which values cross level, linear between points; None when they do not."""
    for k in range(1, len(t)):
        a, b = values[k - 1] - level, values[k] - level
        if a == 0 or (a < 0) != (b < 0) or b == 0:
            return t[k - 1] + (a / (a - b) if a != b else 0.0) * (t[k] - t[k - 1])
    return None


def sweep_numbers(rows):
    """Where layer 13's substrate reaches T_g and where its healing falls to 0.9."""
    t = [float(r["layer_time_s"]) for r in rows]
    substrate = [float(r["substrate_c"]) for r in rows]
    healing = [float(r["healing_mean"]) for r in rows]
    for name, values, level in (("substrate at T_g 110 C", substrate, 110.0),
                                ("healing at the required 0.9", healing, 0.9)):
        at = crossing(t, values, level)
        print(f"layer time with the {name}: " + (f"{at:.1f} s" if at is not None else "not within the sweep"))


def camera_spots_plot(rows, path):
    """Camera spots of layers 1, 15, 30 (model) against the paper's 1-D model, by time since landing."""
    fig = Figure(760, 440, "Compton wall, middle of layers 1, 15 and 30 seen from the side")
    plot = Plot(fig, (80, 40, 740, 380), (0, 600), (50, 200), "time since the spot landed, s",
                "temperature, °C")
    entries = []
    for k, layer in enumerate(sorted({int(r["paper_layer"]) for r in rows})):
        mine = [r for r in rows if int(r["paper_layer"]) == layer]
        t = [float(r["time_since_landing_s"]) for r in mine]
        colour = COLOURS[k % len(COLOURS)]
        plot.line(t, [float(r["model_c"]) for r in mine], colour, width=2.5 - 0.7 * k)
        plot.line(t, [float(r["papers_1d_model_c"]) for r in mine], colour, dashed=True, width=2.5 - 0.7 * k)
        entries.append((f"layer {layer}", colour, False))
    entries += [("beadtwin, camera spot (side strip, cell mean)", "black", False),
                ("the paper's 1-D model (stand-in for its IR data)", "black", True)]
    plot.legend(entries, x=plot.left + 330)
    fig.write(path)


def layer_time_plot(rows, evidence, path):
    """Layer 13's substrate temperature and healing against layer time, with the printable layer times."""
    t = [float(r["layer_time_s"]) for r in rows]
    x_range = (0, 320)
    fig = Figure(760, 640, "Compton wall, layer 13 printed at layer times from 40 to 300 s")
    top = Plot(fig, (80, 40, 740, 300), x_range, (50, 200), "layer time, s", "substrate as it lands, °C")
    bottom = Plot(fig, (80, 360, 740, 580), x_range, (0, 1), "layer time, s", "mean degree of healing")
    substrate = [float(r["substrate_c"]) for r in rows]
    healing = [float(r["healing_mean"]) for r in rows]
    top.hline(110, "#555555", "T_g 110 °C")
    top.line(t, substrate, COLOURS[0])
    top.dots(t, substrate, COLOURS[0])
    bottom.hline(0.9, "#555555", "required 0.9")
    bottom.line(t, healing, COLOURS[1])
    bottom.dots(t, healing, COLOURS[1])
    for row in evidence:
        x = float(row["layer_time_s"])
        if x_range[0] <= x <= x_range[1]:
            top.vline(x, "#2ca02c", f'{row["id"]}: {row["kind"].replace("_", " ")}')
            bottom.vline(x, "#2ca02c")
    top.legend([("substrate surface, as a camera reads it", COLOURS[0], False)], x=top.left + 330)
    fig.write(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--images", default=os.path.join(ROOT, "docs", "images"))
    args = parser.parse_args()
    program = os.path.join(args.build, "tests", "scenarios_tests")
    with tempfile.TemporaryDirectory() as out:
        env = dict(os.environ, BEADTWIN_VALIDATION_OUT=out)
        run = subprocess.run([program, "--gtest_filter=Validation.*"], env=env, text=True,
                             capture_output=True)
        for line in run.stdout.splitlines():
            if line.startswith(("[ RUN", "[       OK", "[  SKIPPED", "[  FAILED")) or "Skipped" in line \
                    or line.startswith(("camera", "layer time", "the middle")):
                print(line)
        if run.returncode != 0:
            print(run.stdout[-4000:], run.stderr[-2000:], file=sys.stderr)
            return run.returncode
        evidence = read_csv(os.path.join(ROOT, "tests", "data", "validation", "printable_layer_times.csv"))
        spots = read_csv(os.path.join(out, "camera_spots.csv"))
        sweep = read_csv(os.path.join(out, "layer_time_sweep.csv"))
        camera_spots_numbers(spots)
        sweep_numbers(sweep)
        camera_spots_plot(spots, os.path.join(args.images, "validation-camera-spots.svg"))
        layer_time_plot(sweep, evidence, os.path.join(args.images, "validation-layer-time.svg"))
    print(f"pictures in {args.images}: validation-camera-spots.svg, validation-layer-time.svg")
    return 0


if __name__ == "__main__":
    sys.exit(main())
