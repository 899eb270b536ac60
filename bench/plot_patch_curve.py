#!/usr/bin/env python3
"""RMS limit error and irregular vertices against the patch count, this product against the stock
baseline (issue 13), from the tables `bench/pipeline_bench.sh --patches N1,N2,...` prints.

    bench/pipeline_bench.sh --runs 1 --patches 200,400,1000 MESH... > table.txt
    python3 bench/plot_patch_curve.py table.txt [more tables...] -o docs/img/patch_curve.png

Documentation only: needs matplotlib (`pip install matplotlib` in any venv); the tests do not
run it."""
import argparse
import re
from collections import defaultdict

ROW = re.compile(r"^(\S+)\.off \(\d+k\)\s+(ours|stock) @(\d+)\s+(\d+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)")


def read(paths):
    data = defaultdict(list)  # (mesh, alg) -> [(patches, irregular, rms L, rms D)]
    for p in paths:
        for line in open(p):
            m = ROW.match(line)
            if m:
                mesh, alg, _, patches, irr, _, rmsl, rmsd = m.groups()
                data[(mesh, alg)].append((int(patches), int(irr), float(rmsl), float(rmsd)))
    return {k: sorted(v) for k, v in data.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("tables", nargs="+")
    ap.add_argument("-o", "--out", default="patch_curve.png")
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    data = read(a.tables)
    meshes = sorted({m for m, _ in data})
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    colours = dict(zip(meshes, ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]))
    for (mesh, alg), rows in sorted(data.items()):
        x = [r[0] for r in rows]
        style = "-o" if alg == "ours" else "--s"
        label = f"{mesh}: {'this product' if alg == 'ours' else 'stock QEC + pairing'}"
        ax[0].plot(x, [r[2] for r in rows], style, color=colours[mesh], label=label, ms=4)
        ax[1].plot(x, [r[1] for r in rows], style, color=colours[mesh], label=label, ms=4)
    ax[0].set(xscale="log", yscale="log", xlabel="patches", ylabel="RMS limit error (‰ of bbox diagonal)",
              title="Fit of the limit surface (lower is better)")
    ax[1].set(xscale="log", yscale="log", xlabel="patches", ylabel="irregular vertices",
              title="Irregular vertices (lower is better)")
    ticks = sorted({r[0] for rows in data.values() for r in rows})
    ticks = [t for t in [200, 300, 400, 700, 1000, 1500, 2000, 3000, 5000] if ticks and ticks[0] * 0.8 <= t <= ticks[-1] * 1.2]
    for x in ax:
        x.grid(True, which="both", alpha=0.3)
        x.set_xticks(ticks)
        x.set_xticklabels([str(t) for t in ticks])
        x.minorticks_off()
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(a.out, dpi=90)
    print(f"wrote {a.out}: {', '.join(f'{m}/{alg} {len(r)} counts' for (m, alg), r in sorted(data.items()))}")


if __name__ == "__main__":
    main()
