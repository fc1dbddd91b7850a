#!/usr/bin/env python3
"""Reads the runs of run.sh and prints the side-by-side table.

  report.py liggghts LOG DUMP PARAMS   one JSON line for a LIGGGHTS run
  report.py spillage OUTDIR PARAMS SOLVER   one JSON line for a spillage run with --solver SOLVER
  report.py table RESULTS.jsonl        the table and the ratios

PARAMS is the `eval`-able output of case_params.py (the box walls and the diameter, to count
wall contacts from LIGGGHTS' final positions). Particle-steps per second = particles × DEM
sub-steps / seconds of the time loop (LIGGGHTS: "Loop time"; spillage: summary.json
timings_s.steps, which excludes start-up and output).
"""
import csv
import json
import math
import os
import re
import statistics
import struct
import sys


def params(path):
    values = {}
    with open(path) as f:
        for line in f:
            key, _, value = line.strip().partition("=")
            if key:
                value = value.strip("'")
                try:
                    values[key] = float(value)
                except ValueError:
                    values[key] = value
    return values


def wall_contacts(p, positions):
    """Sphere–plane contacts with the six box faces (centre closer than a radius)."""
    r = 0.5 * p["diameter"]
    n = 0
    for x, y, z in positions:
        for c, lo, hi in ((x, p["bx0"], p["bx1"]), (y, p["by0"], p["by1"]), (z, p["bz0"], p["bz1"])):
            n += (c - lo < r) + (hi - c < r)
    return n


def with_context(row):
    """The row with what run.sh says of the run: its round (ROUNDS) and the two threads'
    hand-off in ns timed just before it (HANDOFF_NS, absent without the core_to_core example)."""
    row["round"] = int(os.environ.get("ROUND", "1"))
    handoff = os.environ.get("HANDOFF_NS", "")
    if handoff:
        row["handoff_ns"] = float(handoff)
    return row


def liggghts(log_path, dump_path, params_path):
    p = params(params_path)
    text = open(log_path).read()
    loop = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    if not loop:
        sys.exit(f"report.py: no 'Loop time' line in {log_path}")
    seconds, procs, steps, atoms = float(loop[-1][0]), int(loop[-1][1]), int(loop[-1][2]), int(loop[-1][3])
    # last thermo row: Step Atoms ke rke csum zmean
    header = None
    last = None
    for line in text.splitlines():
        words = line.split()
        if words[:2] == ["Step", "Atoms"]:
            header = words
        elif header and len(words) == len(header) and all(re.fullmatch(r"[0-9.eE+-]+", w) for w in words):
            last = dict(zip(header, map(float, words)))
    positions = []
    with open(dump_path) as f:
        lines = f.read().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    for l in lines[start:]:
        w = l.split()
        positions.append((float(w[1]), float(w[2]), float(w[3])))
    pair = int(round(last["csum"] / 2)) if last else None
    row = {
        "code": "LIGGGHTS 3.8",
        "procs": procs,
        "particles": atoms,
        "substeps": steps,
        "seconds": seconds,
        "particle_steps_per_s": atoms * steps / seconds,
        "kinetic_energy": last["ket"] + last["rke"] if last else None,
        "contacts": pair + wall_contacts(p, positions) if last else None,
        "pair_contacts": pair,
        "mean_z": sum(q[2] for q in positions) / len(positions),
        "start_particles": int(p["n_particles"]),
    }
    print(json.dumps(with_context(row)))


def read_vtp(path):
    """The particle centres of a spillage .vtp (ascii or appended raw, UInt64 headers)."""
    data = open(path, "rb").read()
    head, _, appended = data.partition(b"<AppendedData encoding=\"raw\">")
    head = head.decode()
    m = re.search(r'<DataArray type="Float64" Name="Points" NumberOfComponents="3" (format="appended" offset="(\d+)"/>|format="ascii">(.*?)</DataArray>)', head, re.S)
    if m is None:
        sys.exit(f"report.py: no Points array in {path}")
    if m.group(2) is not None:
        base = appended.index(b"_") + 1 + int(m.group(2))
        (nbytes,) = struct.unpack_from("<Q", appended, base)
        values = struct.unpack_from(f"<{nbytes // 8}d", appended, base + 8)
    else:
        values = [float(v) for v in m.group(3).split()]
    return [tuple(values[i : i + 3]) for i in range(0, len(values), 3)]


def spillage(out, params_path, requested):
    p = params(params_path)
    summary = json.load(open(f"{out}/summary.json"))
    with open(f"{out}/series.csv") as f:
        rows = list(csv.DictReader(f))
    substeps = int(sum(float(r["substeps"]) for r in rows))
    seconds = summary["timings_s"]["steps"]
    last = rows[-1]
    mean_z = None
    particles = int(float(last.get("particles") or p["n_particles"]))
    try:
        pvd = open(f"{out}/particles.pvd").read()
        frame = re.findall(r'file="([^"]+)"', pvd)[-1]
        centres = read_vtp(f"{out}/{frame}")
        mean_z = sum(c[2] for c in centres) / len(centres)
    except (OSError, IndexError):
        pass
    # the solver that ran: `--solver fast` without a fast DEM runs the reference DEM
    ran = summary.get("solver", "?")
    row = {
        "code": f"spillage {requested}",
        "ran": ran,
        "procs": int(summary["details"].get("threads", 0)),
        "particles": particles,
        "substeps": substeps,
        "seconds": seconds,
        "particle_steps_per_s": particles * substeps / seconds,
        "kinetic_energy": float(last["particle_kinetic_energy"]),
        "contacts": int(float(last["contacts"])),
        "pair_contacts": None,
        "mean_z": mean_z,
        "start_particles": int(p["n_particles"]),
        "status": summary["details"].get("status", "?"),
        # the fast DEM's pair kernel on this processor (AVX-512, AVX or portable lanes)
        "pair_kernel": summary["details"].get("dem_pair_kernel"),
    }
    print(json.dumps(with_context(row)))


# A hand-off at least this long marks the slow period of the 2-core VM (25–50 ns fast,
# 175–260 ns slow; README, "A gang or one thread, by the clock").
SLOW_HANDOFF_NS = 100.0


def fmt(value, spec):
    return "—" if value is None else format(value, spec)


def table(path):
    rows = [json.loads(l) for l in open(path) if l.strip()]
    print(f"{'code':<22} {'cores':>5} {'particles':>9} {'sub-steps':>9} {'loop s':>8} {'particle-steps/s':>16}   {'KE end [J]':>10} {'contacts':>8} {'mean z [m]':>11}")
    for r in rows:
        lost = "" if r["particles"] == r["start_particles"] else f"  ({r['start_particles'] - r['particles']} lost)"
        if r.get("ran") and r["ran"] != r["code"].split()[-1]:
            lost += f"  (ran: {r['ran']})"
        print(
            f"{r['code']:<22} {r['procs']:>5} {r['particles']:>9} {r['substeps']:>9} {r['seconds']:>8.2f} {r['particle_steps_per_s']:>16.3e}   "
            f"{fmt(r['kinetic_energy'], '10.4e')} {fmt(r['contacts'], '8d')} {fmt(r['mean_z'], '11.7f')}{lost}"
        )

    def ratios(round_):
        def speed(code, procs):
            found = [r["particle_steps_per_s"] for r in rows if r["code"] == code and r["procs"] == procs and r.get("round", 1) == round_]
            return found[-1] if found else None

        lig1, lig2 = speed("LIGGGHTS 3.8", 1), speed("LIGGGHTS 3.8", 2)
        fast1, fast2 = speed("spillage fast", 1), speed("spillage fast", 2)
        ref1 = speed("spillage reference", 1)
        return [
            ("fast / LIGGGHTS, 1 core", fast1, lig1, "target ≥ 1.5"),
            ("fast 2 threads / 1 thread", fast2, fast1, "target ≥ 1.8"),
            ("LIGGGHTS 2 procs / 1 proc", lig2, lig1, ""),
            ("fast / reference, 1 thread", fast1, ref1, ""),
            ("reference / LIGGGHTS, 1 core", ref1, lig1, ""),
        ]

    if not rows:
        return
    rounds = sorted({r.get("round", 1) for r in rows})
    per_round = [ratios(n) for n in rounds]
    for k, (name, _, _, note) in enumerate(per_round[0]):
        values = [rs[k][1] / rs[k][2] for rs in per_round if rs[k][1] is not None and rs[k][2] is not None]
        if not values:
            continue
        if len(rounds) == 1:
            print(f"{name:<30} {values[0]:7.3f}  {note}")
        else:
            # each round's ratio is taken within the round (the machine drifts between rounds)
            listed = ", ".join(f"{v:.3f}" for v in values)
            print(f"{name:<30} {statistics.median(values):7.3f}  median of {len(values)} rounds ({listed})  {note}")
    handoffs = {n: [r["handoff_ns"] for r in rows if r.get("round", 1) == n and "handoff_ns" in r] for n in rounds}
    if any(handoffs.values()):
        # a round is slow when any of its runs began with a slow hand-off (the 2-core VM's
        # periods: 25–50 ns and 175–260 ns); the 1 → 2 ratio of each kind of round apart
        slow = {n: bool(h) and max(h) >= SLOW_HANDOFF_NS for n, h in handoffs.items()}
        listed = ", ".join(f"{max(h):.0f}" if h else "—" for h in handoffs.values())
        print(f"two threads' hand-off, ns (the slowest before a run of each round): {listed}")
        k = next(k for k, r in enumerate(per_round[0]) if r[0] == "fast 2 threads / 1 thread")
        for kind, want in (("fast", False), ("slow", True)):
            values = [rs[k][1] / rs[k][2] for n, rs in zip(rounds, per_round) if handoffs[n] and slow[n] == want and rs[k][1] and rs[k][2]]
            if values:
                print(f"  fast 2 threads / 1 thread in {kind}-hand-off rounds: median {statistics.median(values):.3f} of {len(values)}")
    kernels = sorted({r["pair_kernel"] for r in rows if r.get("pair_kernel")})
    if kernels:
        print(f"spillage fast pair kernel: {', '.join(kernels)}")
    if any(r.get("status", "").startswith("failed") for r in rows):
        print("note: a spillage run failed (see its summary.json)")
    if len({r["substeps"] for r in rows}) > 1:
        print("note: the runs differ in length: compare speeds and end states only between runs of equal sub-steps")


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else ""
    if what == "liggghts" and len(sys.argv) == 5:
        liggghts(*sys.argv[2:])
    elif what == "spillage" and len(sys.argv) == 5:
        spillage(*sys.argv[2:])
    elif what == "table" and len(sys.argv) == 3:
        table(sys.argv[2])
    else:
        sys.exit(__doc__)
