#!/usr/bin/python3
"""Picture of a crowned 3D gear-body mesh written by `hertzgear mesh` (MSH 2.2 ASCII).

Left: the boundary quadrilaterals of the body (flanks coloured by physical group).
Right: material removed from the nominal involute at the drive-flank nodes of the central
tooth, against the face position z, with the crowning parabola beta (2z/b)^2.

    hertzgear mesh data/scenes/paper_crowned.prm --out /tmp/m \
        --set Stiffness/fe_level=0 --set Mesh/teeth_per_sector=3
    /usr/bin/python3 scripts/plot_gear_mesh.py /tmp/m/pinion.msh docs/figures/crowned_pinion_mesh.png \
        --teeth 23 --module 3 --face-width 20 --crowning-um 80 --backlash 0.1172
"""
import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_msh22(path):
    nodes, elements, names = {}, [], {}
    with open(path) as f:
        lines = iter(f.read().split("\n"))
    for line in lines:
        if line == "$PhysicalNames":
            for _ in range(int(next(lines))):
                dim, tag, name = next(lines).split()
                names[(int(dim), int(tag))] = name.strip('"')
        elif line == "$Nodes":
            for _ in range(int(next(lines))):
                t, x, y, z = next(lines).split()
                nodes[int(t)] = (float(x), float(y), float(z))
        elif line == "$Elements":
            for _ in range(int(next(lines))):
                v = [int(s) for s in next(lines).split()]
                etype, ntags = v[1], v[2]
                elements.append((etype, v[3], v[3 + ntags:]))
    return nodes, elements, names


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("msh")
    ap.add_argument("png")
    ap.add_argument("--teeth", type=int, required=True)
    ap.add_argument("--module", type=float, required=True)
    ap.add_argument("--face-width", type=float, required=True)
    ap.add_argument("--crowning-um", type=float, required=True)
    ap.add_argument("--backlash", type=float, default=0.0, help="total backlash along the line of action [mm]")
    ap.add_argument("--pressure-angle-deg", type=float, default=20.0)
    ap.add_argument("--teeth-per-sector", type=int, default=3)
    a = ap.parse_args()

    nodes, elements, names = read_msh22(a.msh)
    quads = [(phys, conn) for etype, phys, conn in elements if etype == 3]

    fig = plt.figure(figsize=(12, 5.5))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    colours = {"drive_flank": "#d62728", "coast_flank": "#1f77b4", "drive_fillet": "#ff9896",
               "coast_fillet": "#aec7e8"}
    polys, faces = [], []
    for phys, conn in quads:
        name = names.get((2, phys), "")
        key = name.rsplit("_", 1)[0] if name[-1:].isdigit() else name
        polys.append([nodes[n] for n in conn])
        faces.append(colours.get(key, "#d9d9d9"))
    ax.add_collection3d(Poly3DCollection(polys, facecolors=faces, edgecolors="k", linewidths=0.08))
    xs = [p[0] for p in nodes.values()]
    ys = [p[1] for p in nodes.values()]
    zs = [p[2] for p in nodes.values()]
    ax.set_xlim(min(xs), max(xs)); ax.set_ylim(min(ys), max(ys)); ax.set_zlim(min(zs), max(zs))
    ax.set_box_aspect((max(xs) - min(xs), max(ys) - min(ys), max(zs) - min(zs)))
    ax.view_init(elev=22, azim=-15)
    ax.set_xlabel("x [mm]"); ax.set_ylabel("y [mm]"); ax.set_zlabel("z [mm]")
    ax.set_title("%d hexahedra, drive flanks red, coast flanks blue" %
                 sum(1 for e in elements if e[0] == 5))

    # Removal from the nominal involute at the drive-flank nodes of the central tooth.
    alpha = math.radians(a.pressure_angle_deg)
    r = 0.5 * a.module * a.teeth
    rb = r * math.cos(alpha)
    s = math.pi * a.module / 2 - a.backlash / (2 * math.cos(alpha))
    psi = s / (2 * r) + math.tan(alpha) - alpha
    central = a.teeth_per_sector // 2
    flank_tag = [t for (d, t), n in names.items() if d == 2 and n == "drive_flank_%d" % central][0]
    ids = {n for phys, conn in quads if phys == flank_tag for n in conn}
    zz, dd = [], []
    for n in ids:
        x, y, z = nodes[n]
        rad = math.hypot(x, y)
        ar = math.acos(min(1.0, rb / rad))
        phi = math.atan2(y, x)
        zz.append(z)
        dd.append(1e3 * rb * (psi - (math.tan(ar) - ar) - abs(phi)))
    ax2 = fig.add_subplot(1, 2, 2)
    b, beta = a.face_width, a.crowning_um
    zc = [-b / 2 + b * i / 200 for i in range(201)]
    ax2.plot(zc, [beta * (2 * z / b) ** 2 for z in zc], "k-", lw=1, label=r"$\Delta(z)=\beta(2z/b)^2$")
    ax2.plot(zz, dd, "o", ms=3, color="#d62728", label="drive-flank nodes (all radii)")
    ax2.set_xlabel("z [mm]"); ax2.set_ylabel(r"removal from the involute [$\mu$m]")
    ax2.set_title(r"lead crowning $\beta$ = %g $\mu$m at the mesh nodes" % beta)
    ax2.grid(alpha=0.3); ax2.legend()
    fig.tight_layout()
    fig.savefig(a.png, dpi=130)


if __name__ == "__main__":
    main()
