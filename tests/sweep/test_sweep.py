#!/usr/bin/env python3
"""`woven sweep` end to end (docs/SWEEP-FORMAT.md), on tiny Cusick plans (3 cm spacing, 73
particles, 0.3 s a point; 2 cm, 0.7 s, where a rank is killed mid-run):

  test_sweep.py single WOVEN   one process, --jobs 2: every point once, the merged table, resume
                               (nothing reruns), a corrupted point and a failing point rerun,
                               --merge idempotent, --shard and a Slurm array's environment.
  test_sweep.py mpi WOVEN      `mpirun -n 2` (Open MPI, as root with --oversubscribe): every point
                               once and the table complete; then a rank killed mid-run (SIGTERM,
                               then SIGKILL) and the sweep run again: only the missing points run,
                               nothing done before is lost or run twice.
  test_sweep.py report WOVEN   `woven report` on a sweep, opened in headless Chromium (software GL):
                               the page's data-ready flag, its table's rows, a screenshot that is
                               not blank; a broken folder gives a one-line error.
"""
import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "render"))
import test_report_pages as pages  # noqa: E402  (Chromium, PNG pixels, the plots' check)

FAILURES = []


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print("FAIL:", what, flush=True)


def plan_text(seeds, extra_axes="", options="", spacing=3):
    return f"""name = "t"
command = "cusick"
[axes]
fabric = ["cotton", "wool"]
seed = {seeds}
{extra_axes}
[options]
spacing_cm = {spacing}
threads = 1
render = false
{options}
"""


def run(cmd, env=None, check_rc=None):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if check_rc is not None and p.returncode != check_rc:
        FAILURES.append(f"{' '.join(cmd)}: exit {p.returncode}, expected {check_rc}\n{p.stdout}\n{p.stderr}")
        print("FAIL:", FAILURES[-1], flush=True)
    return p


def ran_points(text):
    """The points a sweep's output says it ran ("[k/n] NAME: ran in ...")."""
    return re.findall(r"^\[\d+/\d+\] (\S+): ran in", text, re.M)


def table(sweep):
    with open(os.path.join(sweep, "sweep.csv")) as f:
        return list(csv.DictReader(f))


def run_ids(sweep):
    out = {}
    for name in os.listdir(sweep):
        pj = os.path.join(sweep, name, "point.json")
        if os.path.isfile(pj):
            out[name] = json.load(open(pj))["run_id"]
    return out


def test_single(woven, tmp):
    plan = os.path.join(tmp, "plan.toml")
    open(plan, "w").write(plan_text("[1, 2, 3]"))
    sweep = os.path.join(tmp, "single")
    p = run([woven, "sweep", plan, "--out", sweep, "--jobs", "2"], check_rc=0)
    names = sorted(ran_points(p.stderr))
    check(len(names) == 6 and len(set(names)) == 6, f"6 points each run once: {names}")
    # Progress on stderr, the summary alone on stdout; the thread count the points ran (the plan's).
    check("ran in" not in p.stdout and p.stdout.startswith("ran 6, failed 0"), f"stdout: the summary only: {p.stdout}")
    check("2 jobs of 1 thread (the plan's --threads)" in p.stderr, f"the points' thread count: {p.stderr}")
    rows = table(sweep)
    check([r["status"] for r in rows] == ["done"] * 6, "merged table: 6 rows done")
    check(rows[0]["point"] == "fabric-cotton_seed-1" and rows[5]["point"] == "fabric-wool_seed-3", "rows in plan order")
    dc = {r["point"]: float(r["drape_coefficient_percent"]) for r in rows}
    # Cotton is stiffer than wool: DC 52.7 % against 33.6 % on this coarse grid (seeds 1-3).
    check(all(50 < dc[f"fabric-cotton_seed-{s}"] < 56 for s in (1, 2, 3)), f"cotton DC: {dc}")
    check(all(31 < dc[f"fabric-wool_seed-{s}"] < 36 for s in (1, 2, 3)), f"wool DC: {dc}")
    # The same numbers as the command run by hand.
    hand = os.path.join(tmp, "hand")
    run([woven, "cusick", "wool", "--seed", "2", "--spacing-cm", "3", "--threads", "1", "--no-render", "--out", hand], check_rc=0)
    check(abs(json.load(open(os.path.join(hand, "cusick.json")))["drape_coefficient_percent"] - dc["fabric-wool_seed-2"]) < 1e-9,
          "a point's DC equals `woven cusick` run by hand")
    check(run([woven, "check", os.path.join(sweep, "fabric-wool_seed-2")]).returncode == 0, "a point's folder passes woven check")
    ids = run_ids(sweep)
    # Resume: nothing runs again.
    p = run([woven, "sweep", plan, "--out", sweep], check_rc=0)
    check(ran_points(p.stderr) == [] and "6 done already, 0 to run" in p.stderr, "resume: nothing reruns")
    check(run_ids(sweep) == ids, "resume: the folders are untouched")
    # A point whose file changed, and one whose folder lost its manifest, run again; only those.
    obj = os.path.join(sweep, "fabric-cotton_seed-2", "cusick.obj")
    with open(obj, "r+b") as f:
        f.seek(100)
        f.write(b"#")
    os.remove(os.path.join(sweep, "fabric-wool_seed-3", "cusick.json"))
    p = run([woven, "sweep", plan, "--out", sweep], check_rc=0)
    check(sorted(ran_points(p.stderr)) == ["fabric-cotton_seed-2", "fabric-wool_seed-3"], f"only the broken points rerun: {p.stderr}")
    check("sha256" in p.stderr, "the rerun says why (the changed file's hash)")
    ids2 = run_ids(sweep)
    check(all(ids2[n] == ids[n] for n in ids if n not in ("fabric-cotton_seed-2", "fabric-wool_seed-3")), "the others kept")
    # A changed plan (another spacing) is another command line: every point runs again.
    open(plan, "w").write(plan_text("[1]").replace("spacing_cm = 3", "spacing_cm = 2.5"))
    p = run([woven, "sweep", plan, "--out", sweep], check_rc=0)
    check(len(ran_points(p.stderr)) == 2, "a changed option reruns the points")
    # A failing point (a disc larger than the specimen): recorded, exit 1, the others done; the
    # merged table says failed; the next run tries it again.
    open(plan, "w").write(plan_text("[1]", 'disc_cm = [18, 40]'))
    failing = os.path.join(tmp, "failing")
    p = run([woven, "sweep", plan, "--out", failing], check_rc=1)
    rows = {r["point"]: r for r in table(failing)}
    check(rows["fabric-cotton_seed-1_disc_cm-40"]["status"] == "failed", "the failing point is 'failed' in the table")
    check(rows["fabric-cotton_seed-1_disc_cm-18"]["status"] == "done", "the others are done")
    rec = json.load(open(os.path.join(failing, "failed", "fabric-cotton_seed-1_disc_cm-40.json")))
    check(rec["exit_code"] == 2 and "disc" in rec["log_tail"], f"the failure record: {rec}")
    p = run([woven, "sweep", plan, "--out", failing], check_rc=1)
    check(sorted(ran_points(p.stderr)) == [] and p.stderr.count("FAILED") == 2, "failed points are tried again, the others not")
    # --merge is idempotent; the files are whole.
    a = open(os.path.join(failing, "sweep.csv")).read()
    run([woven, "sweep", plan, "--out", failing, "--merge"], check_rc=0)
    run([woven, "sweep", plan, "--out", failing, "--merge"], check_rc=0)
    check(open(os.path.join(failing, "sweep.csv")).read() == a, "--merge twice: the same table")
    check(json.load(open(os.path.join(failing, "sweep.json")))["failed"] == 2, "sweep.json counts")
    # Shards: --shard and a Slurm array's environment split the plan; two shards cover it.
    open(plan, "w").write(plan_text("[1, 2]"))
    sh = os.path.join(tmp, "shards")
    p0 = run([woven, "sweep", plan, "--out", sh, "--shard", "0/2"], check_rc=0)
    # srun inside an array task sets a PMI world of one: the array's split still holds.
    env = dict(os.environ, SLURM_ARRAY_TASK_ID="8", SLURM_ARRAY_TASK_COUNT="2", SLURM_ARRAY_TASK_MIN="7", PMI_RANK="0", PMI_SIZE="1")
    p1 = run([woven, "sweep", plan, "--out", sh], env=env, check_rc=0)
    check(sorted(ran_points(p0.stderr)) == ["fabric-cotton_seed-1", "fabric-wool_seed-1"], f"shard 0/2: {p0.stderr}")
    check(sorted(ran_points(p1.stderr)) == ["fabric-cotton_seed-2", "fabric-wool_seed-2"] and "(Slurm array)" in p1.stderr,
          f"Slurm task 8 of 7-8: {p1.stderr}")
    check([r["status"] for r in table(sh)] == ["done"] * 4, "the last shard's merge is complete")
    bad = run([woven, "sweep", plan, "--out", sh, "--shard", "2/2"], check_rc=2)
    check(bad.stderr.startswith("woven: error: command line: --shard: expected I/N") and bad.stderr.count("\n") == 1, bad.stderr)
    bad = run([woven, "sweep", plan, "--out", sh], env=dict(os.environ, OMPI_COMM_WORLD_RANK="3", OMPI_COMM_WORLD_SIZE="2"), check_rc=2)
    check("environment: OMPI_COMM_WORLD_RANK: expected a rank below OMPI_COMM_WORLD_SIZE (2), got 3" in bad.stderr, bad.stderr)
    bad = run([woven, "sweep", plan, "--out", sh], env=dict(os.environ, PMI_RANK="x", PMI_SIZE="2"), check_rc=2)
    check("woven: error: environment: PMI_RANK: expected an integer in [0, 1000000000], got 'x'" in bad.stderr, bad.stderr)


def mpirun(woven, plan, sweep):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    return ["mpirun", "-n", "2", "--oversubscribe", woven, "sweep", plan, "--out", sweep], env


def rank_pid(plan, rank):
    """The `woven sweep` process of an Open MPI rank (found by its command line and environment)."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            cmd = open(f"/proc/{pid}/cmdline", "rb").read().split(b"\0")
            if b"sweep" not in cmd or plan.encode() not in cmd or cmd[0].endswith(b"mpirun"):
                continue
            envs = open(f"/proc/{pid}/environ", "rb").read().split(b"\0")
            if f"OMPI_COMM_WORLD_RANK={rank}".encode() in envs:
                return int(pid)
        except OSError:
            continue
    return None


def test_mpi(woven, tmp):
    plan = os.path.join(tmp, "plan.toml")
    open(plan, "w").write(plan_text("[1, 2, 3]", spacing=2))
    # Every point once, the merged table complete.
    sweep = os.path.join(tmp, "mpi")
    cmd, env = mpirun(woven, plan, sweep)
    p = run(cmd, env=env, check_rc=0)
    names = ran_points(p.stderr)
    check(len(names) == 6 and len(set(names)) == 6, f"mpirun -n 2: 6 points each run once: {sorted(names)}")
    check("shard 0/2 (Open MPI): 3 here" in p.stderr and "shard 1/2 (Open MPI): 3 here" in p.stderr, "two ranks of 3 points")
    check([r["status"] for r in table(sweep)] == ["done"] * 6, "the merged table is complete")
    # A rank killed mid-run, then the same command again.
    for sig in (signal.SIGTERM, signal.SIGKILL):
        sweep = os.path.join(tmp, f"killed-{sig.name}")
        cmd, env = mpirun(woven, plan, sweep)
        job = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.time() + 60
        victim = None
        while time.time() < deadline:
            if victim is None:
                victim = rank_pid(plan, 0)
            if victim and os.path.isdir(sweep) and len(run_ids(sweep)) >= 1:
                break
            time.sleep(0.05)
        check(victim is not None, f"{sig.name}: found rank 0")
        before = run_ids(sweep)
        if victim:
            os.kill(victim, sig)
        _, out1 = job.communicate(timeout=120)
        check(job.returncode != 0, f"{sig.name}: the killed job does not succeed")
        first = run_ids(sweep)
        check(len(first) < 6, f"{sig.name}: killed before the end ({len(first)} of 6 done)")
        check(not any(n.startswith(".woven-tmp") for n in os.listdir(sweep)), "no temporaries in the sweep folder")
        # No half point: every folder there verifies.
        for n in first:
            check(run([woven, "check", os.path.join(sweep, n)]).returncode == 0, f"{sig.name}: {n} verifies after the kill")
        p = run(cmd, env=env, check_rc=0)
        again = ran_points(p.stderr)
        missing = sorted(set(table(sweep)[i]["point"] for i in range(6)) - set(first))
        check(sorted(again) == missing, f"{sig.name}: the rerun ran exactly the missing points: {sorted(again)} vs {missing}")
        after = run_ids(sweep)
        check(all(after[n] == first[n] for n in first), f"{sig.name}: the points done before the kill are kept")
        check(sorted(ran_points(out1) + again) == sorted(after), f"{sig.name}: every point ran exactly once over both runs")
        check([r["status"] for r in table(sweep)] == ["done"] * 6, f"{sig.name}: the merged table is complete")
        work = os.path.join(sweep, ".work")
        check(not os.path.isdir(work) or os.listdir(work) == [], f"{sig.name}: no work folder left: {os.listdir(work)}")
        del before


def test_report(woven, tmp):
    plan = os.path.join(tmp, "plan.toml")
    open(plan, "w").write(plan_text("[1, 2]"))
    sweep = os.path.join(tmp, "report")
    run([woven, "sweep", plan, "--out", sweep], check_rc=0)
    p = run([woven, "report", sweep], check_rc=0)
    page = os.path.join(sweep, "report.html")
    html = open(page).read()
    outside = re.findall(r"<(?:script|img|link|iframe|source)\b[^>]*\b(?:src|href)\s*=\s*[\"'](?!data:)[^\"']*", html)
    check(outside == [] and ' src="data:image/png;base64,' in html, f"the page fetches nothing (pictures inlined): {outside[:3]}")
    check(html.count("<svg") >= 1 and "THREE" in html, "SVG plot and three.js inlined")
    dom = pages.chromium(["--dump-dom", "file://" + page])
    body = re.search(r"<body[^>]*>", dom.stdout)
    check(body and 'data-ready="1"' in body.group(0), f"Chromium: the page sets data-ready: {body.group(0) if body else dom.stderr[-500:]}")
    check(body and 'data-view="webgl"' in body.group(0), "Chromium: the 3-D view was built with WebGL (software GL)")
    table = re.search(r'<table class="sortable" id="points">.*?<tbody>(.*?)</tbody>', dom.stdout, re.S)
    rows = re.findall(r"<tr[^>]*><td>([^<]*)</td>", table.group(1)) if table else []
    check(rows == ["fabric-cotton_seed-1", "fabric-cotton_seed-2", "fabric-wool_seed-1", "fabric-wool_seed-2"], f"the table's rows: {rows}")
    # The plots: SVG vertices back through the axes to the embedded data (test_report_pages.py's
    # check), and the DC plot's points the mean over the seeds of sweep.json's rows per fabric.
    plots = pages.plots_of(dom.stdout)
    for pid, (data, svg) in plots.items():
        pages.check_plot(pid, data, svg)
    FAILURES.extend(pages.FAILURES)
    rows = json.load(open(os.path.join(sweep, "sweep.json")))["rows"]
    dc = {}
    for r in rows:
        dc.setdefault(r["values"]["fabric"], []).append(r["outputs"]["drape_coefficient_percent"])
    means = sorted((sum(v) / len(v), f) for f, v in dc.items())
    first = next((d for d, _ in plots.values() if d["title"].startswith("drape coefficient")), None)
    got = sorted(first["series"][0]["y"]) if first else []
    check(first is not None and len(got) == len(means) and all(abs(a - b[0]) <= 1e-9 * abs(b[0]) for a, b in zip(got, means)),
          f"the DC plot's points are the seeds' means per fabric: {got} vs {means}")
    shot = os.path.join(tmp, "shot.png")
    pages.chromium(["--window-size=1200,1700", "--screenshot=" + shot, "file://" + page])
    check(os.path.isfile(shot), "Chromium wrote the screenshot")
    if os.path.isfile(shot):
        w, h, px, ch = pages.png_pixels(shot)
        colours, cloth = set(), 0
        for line in px[::2]:
            for i in range(0, len(line), ch * 2):
                r, g, b = line[i], line[i + 1], line[i + 2]
                colours.add((r >> 3, g >> 3, b >> 3))
                cloth += 60 < r < 230 and g < r - 40 and b < r - 50  # the cloth's terracotta in the 3-D view
        check(len(colours) > 50, f"the screenshot is not blank ({len(colours)} colours)")
        check(cloth > 5000, f"the 3-D view shows the drape ({cloth} cloth-coloured samples)")
    # A broken folder: a one-line error, and the page is not rewritten.
    before = open(page, "rb").read()
    with open(os.path.join(sweep, "fabric-wool_seed-1", "cusick.obj"), "ab") as f:
        f.write(b"# changed\n")
    p = run([woven, "report", sweep], check_rc=2)
    check(p.stderr.count("\n") == 1 and "fabric-wool_seed-1" in p.stderr and "does not verify" in p.stderr, f"broken folder: {p.stderr}")
    check(open(page, "rb").read() == before, "no half page written")
    p = run([woven, "report", tmp], check_rc=2)
    check("expected a sweep folder" in p.stderr, p.stderr)
    # One kes-test folder: its curves, simulated against input, as SVG plots.
    kes = os.path.join(tmp, "kes")
    run([woven, "kes-test", "wool", "--test", "bending", "--direction", "warp", "--out", kes], check_rc=0)
    run([woven, "report", kes], check_rc=0)
    html = open(os.path.join(kes, "report.html")).read()
    data = re.findall(r'<script type="application/json" class="plot-data"[^>]*>(.*?)</script>', html, re.S)
    labels = [s["label"] for d in data for s in json.loads(d)["series"]]
    check(html.count("<svg") >= 1 and labels == ["input", "simulated warp"], f"kes-test: the bending loop plot, input and simulated: {labels}")


def main():
    which, woven = sys.argv[1], os.path.abspath(sys.argv[2])
    tmp = tempfile.mkdtemp(prefix="woven-sweep-")
    try:
        {"single": test_single, "mpi": test_mpi, "report": test_report}[which](woven, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if FAILURES:
        print(f"{len(FAILURES)} failure(s)")
        sys.exit(1)
    print("ok")


if __name__ == "__main__":
    main()
