#!/usr/bin/env python3
"""PNG plots of the benchmark results in one folder (scripts/bench.sh).

    python3 bench/plot.py DIR

Reads DIR/build.json, frame.json and truth.json (each where present) and
writes, through gnuplot's pngcairo terminal:
  build.png              builder: time per vertex against size; fast against
                         brute force
  frame_techniques.png   1080p frame by technique x diffusion, stacked by pass,
                         one panel per scene
  translucency_pass.png  translucency pass: vertices/s against its bandwidth bound
  update.png             deformation update per vertex, next to the translucency pass
  truth.png              ground truth: time against samples
Each PNG is written beside its name and renamed, so a failed plot leaves no
half picture. Exits 1 naming the file when a result cannot be read or
gnuplot fails.
"""
import json
import os
import subprocess
import sys
import tempfile


def fail(message):
    sys.exit(f"plot.py: {message}")


def load(folder, name):
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        print(f"plot.py: no {path}, so no plot of it", file=sys.stderr)
        return None
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")


def gnuplot(folder, work, name, script, blocks, height=700):
    """Runs `script` with each named data block in `blocks` (name -> rows)
    written to WORK/name.dat; the script's output is OUT, a temporary name."""
    for block, rows in blocks.items():
        with open(os.path.join(work, block + ".dat"), "w") as f:
            for row in rows:
                f.write(" ".join(str(v) for v in row) + "\n")
    png = os.path.join(folder, name)
    header = f"set terminal pngcairo size 1200,{height} noenhanced font ',11'\nset output '{png}.tmp'\ncd '{work}'\n"
    path = os.path.join(work, name + ".gnuplot")
    with open(path, "w") as f:
        f.write(header + script)
    run = subprocess.run(["gnuplot", path], capture_output=True, text=True)
    if run.returncode != 0:
        fail(f"gnuplot failed on {path}:\n{run.stderr}")
    os.replace(png + ".tmp", png)
    print(f"plot.py: {png}", file=sys.stderr)


# Room around the points of line plots, so none sits on an axis.
PAD = "set offsets graph 0.05, graph 0.05, graph 0.05, 0\n"


def plot_build(folder, work, build):
    scaling = [r for r in build.get("scaling", []) if "vertices" in r]
    brute = build.get("brute_force", [])
    if not scaling and not brute:
        return
    script = PAD + "set multiplot layout 1,2 title 'sam_build (skin, N = 3)'\nset grid\nset logscale x\n"
    script += ("set title 'scaling: the same 120 mm knot, denser'\nset xlabel 'vertices'\n"
               "set ylabel 'microseconds per vertex'\nset yrange [0:*]\n"
               "plot 'scaling.dat' using 1:2 with linespoints lw 2 pt 7 notitle, "
               "'' using 1:2:(sprintf('%.1f', $2)) with labels offset 0,1 notitle\n")
    script += ("set title 'fast builder against the O(m^2) brute force (40 mm knots)'\nset logscale y\n"
               "set ylabel 'seconds'\nset yrange [*:*]\nset key top left\n"
               "plot 'brute.dat' using 1:3 with linespoints lw 2 pt 7 title 'brute force', "
               "'' using 1:2 with linespoints lw 2 pt 5 title 'fast', "
               "'' using 1:3:(sprintf('%.0fx', $4)) with labels offset 0,1 notitle\n")
    script += "unset multiplot\n"
    gnuplot(folder, work, "build.png", script, {
        "scaling": [(r["vertices"], r["us_per_vertex"]) for r in scaling],
        "brute": [(r["vertices"], r["fast_seconds"], r["brute_seconds"], r["speedup"]) for r in brute]})


def plot_frame(folder, work, frame):
    size = f"{frame.get('width', 1920)}x{frame.get('height', 1080)}"
    scenes = frame.get("frame_by_technique", [])
    if scenes:
        blocks, script = {}, f"set multiplot layout {len(scenes)},1 title \"whole frame at {size} by pass ({frame['renderer']})\\n\"\n"
        script += ("set style data histograms\nset style histogram rowstacked\nset style fill solid 0.85 border -1\n"
                   "set boxwidth 0.7\nset grid y\nset ylabel 'ms'\nset key outside top center horizontal\n"
                   "set xtics rotate by -30\n")
        for i, scene in enumerate(scenes):
            rows = []
            for f in scene["frames"]:
                if "skipped" in f:
                    continue
                translucency = scene["translucency_ms"] if f["technique"] == "sam" else 0
                rows.append((f"{f['technique']}/{f['diffusion']}", scene["irradiance_ms"], translucency, f["render_ms"]))
            blocks[f"scene{i}"] = rows
            script += (f"set title '{scene['scene']}, {scene['vertices']} vertices (technique/diffusion)'\n"
                       f"plot 'scene{i}.dat' using 2:xtic(1) title 'irradiance (shadow maps, L_d)', "
                       "'' using 3 title 'SAM translucency pass', '' using 4 title 'render (shade, diffusion, read-back)'\n"
                       "unset key\n")
        script += "unset multiplot\n"
        gnuplot(folder, work, "frame_techniques.png", script, blocks, 380 * len(scenes))
    meshes = frame.get("meshes", [])
    if meshes:
        script = (PAD + "set title 'translucency pass (eq. 12 + smoothing): achieved against the memory-bandwidth bound'\n"
                  "set grid\nset logscale xy\nset xlabel 'vertices (knots, skin, N = 3)'\nset ylabel 'vertices per second'\n"
                  "set key top left\n"
                  "plot 'pass.dat' using 1:2 with linespoints lw 2 pt 7 title 'achieved', "
                  "'' using 1:3 with linespoints lw 2 pt 5 dt 2 title sprintf('bound: bytes per vertex / memcpy %.1f GB/s', "
                  f"{frame['memcpy_bandwidth_gb_s']}), "
                  "'' using 1:2:(sprintf('%.0f%%', 100 * $4)) with labels offset 0,-1 notitle\n")
        gnuplot(folder, work, "translucency_pass.png", script, {"pass": [
            (m["vertices"], m["translucency_vertices_per_s"], 1e3 * m["vertices"] / m["bandwidth_bound_ms"],
             m["fraction_of_bound"]) for m in meshes]})
        script = (PAD + "set title 'deformation update (deform pass + sample walk) per vertex'\nset grid\nset logscale x\n"
                  "set xlabel 'vertices (knots bent 60 degrees, skin, N = 3)'\nset ylabel 'nanoseconds per vertex'\n"
                  "set yrange [0:*]\nset key top right\n"
                  "plot 'update.dat' using 1:2 with linespoints lw 2 pt 7 title 'update', "
                  "'' using 1:3 with linespoints lw 2 pt 5 title 'translucency pass at rest', "
                  "'' using 1:4 with linespoints lw 2 pt 9 title 'translucency pass posed (K carried by quadrature)', "
                  "'' using 1:5 with linespoints lw 2 pt 11 title 'translucency pass posed (eq. 15)', "
                  "'' using 1:2:(sprintf('%.0f', $2)) with labels offset 0,1 notitle\n")
        gnuplot(folder, work, "update.png", script, {"update": [
            (m["vertices"], m["update_ns_per_vertex"], m["translucency_ns_per_vertex"],
             m["posed_translucency_ns_per_vertex"], m["eq15_translucency_ns_per_vertex"]) for m in meshes]})


def plot_truth(folder, work, truth):
    scenes = truth.get("scenes", [])
    if not scenes:
        return
    blocks, create, query = {}, [], []
    for i, scene in enumerate(scenes):
        blocks[f"truth{i}"] = [(c["samples"], c["create_seconds"], c["exact_seconds"], c["far_field_seconds"])
                               for c in scene["counts"]]
        name = f"{scene['scene'].replace('.json', '')} ({scene['material']})"
        create.append(f"'truth{i}.dat' using 1:2 with linespoints lw 2 pt 7 lc {i + 1} title '{name}'")
        query.append(f"'truth{i}.dat' using 1:3 with linespoints lw 2 pt 7 lc {i + 1} title '{name}, exact, {scene['queries']} vertices'")
        query.append(f"'truth{i}.dat' using 1:4 with linespoints lw 2 pt 4 dt 2 lc {i + 1} title 'far field 1%'")
    script = (PAD + "set multiplot layout 1,2 title 'ground truth (sam_truth): time against surface samples'\n"
              "set grid\nset logscale xy\nset xlabel 'surface samples'\nset ylabel 'seconds'\nset key top left\n"
              "set title 'placing the samples and their L_d (sam_truth_create)'\nplot " + ", ".join(create) + "\n"
              "set title 'the back-side sum (eq. 7) at the vertices'\n"
              "plot " + ", ".join(query) + "\nunset multiplot\n")
    gnuplot(folder, work, "truth.png", script, blocks)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: python3 bench/plot.py RESULTS_DIR")
    folder = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory(prefix="bench_plot_") as work:
        build = load(folder, "build.json")
        if build:
            plot_build(folder, work, build)
        frame = load(folder, "frame.json")
        if frame:
            plot_frame(folder, work, frame)
        truth = load(folder, "truth.json")
        if truth:
            plot_truth(folder, work, truth)


if __name__ == "__main__":
    main()
