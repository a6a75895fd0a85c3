"""The fluid3d benchmark scene written in Taichi (CPU backend): the peer figure
beside ``geompm bench --scene fluid3d``.

    python -m pip install -e '.[bench]'        # taichi
    python benchmarks/peers/taichi_fluid3d.py [--scheme usl|mls] [--steps 100] [--f32]

Same scene as benchmarks/fluid3d.json: unit cube, 64 cells per side, slip
walls on every face (nodes on and beyond a face lose their velocity into the
wall), Newtonian fluid with mu = 0, Tait EOS P = rho0 c^2 / r ((rho/rho0)^r - 1)
with rho0 = 1 kg/m3, c = 20 m/s, r = 1, the block x [0.1, 0.5], y [0.1, 0.7],
z [0.3, 0.7] m seeded as geompm seeds it (2 particles per cell per direction
at sub-cell centres: 204 204 particles), gravity (0, -9.8, 0), quadratic
B-splines, APIC, dt = 2e-4 s, float64 like geompm.

Schemes:
- ``usl`` (default): geompm's step, the same arithmetic: P2G of mass, APIC
  momentum and internal force f = -V sigma grad w; grid update with gravity;
  walls; G2P of v, C = 4/h^2 sum w v (x_i - x_p)^T and L = sum v (x) grad w;
  V <- V det(I + dt L).
- ``mls``: the lighter MLS-MPM step of Hu et al. (2018) "A moving least squares
  material point method with displacement discontinuity and two-way rigid
  body coupling", ACM TOG 37(4):150, where the stress enters the affine
  momentum and L = C: the plain Taichi fluid step of the issue's 2.7 M figure.

Prints particles, steps, wall seconds and particle-steps per second (two
warm-up steps, which include Taichi's compilation, are not timed).
"""

import argparse
import time

import numpy as np
import taichi as ti

N_CELLS = 64
H = 1.0 / N_CELLS
RHO0, C_SOUND, R_EOS = 1.0, 20.0, 1.0
GRAVITY = (0.0, -9.8, 0.0)
DT = 2e-4
BLOCK = ((0.1, 0.1, 0.3), (0.5, 0.7, 0.7))
PPC = 2


def seed() -> np.ndarray:
    """Sub-cell centres inside the block, as geompm.setup.bodies.lattice seeds a box."""
    axes = []
    for lo, hi in zip(*BLOCK):
        k = np.arange(int(np.floor(lo / H)) * PPC, int(np.ceil(hi / H)) * PPC)
        x = (k + 0.5) * H / PPC
        axes.append(x[(x >= lo) & (x <= hi)])
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=1)


def build(x0: np.ndarray, scheme: str, fp):
    n = len(x0)
    nn = N_CELLS + 1
    vol0 = (H / PPC) ** 3
    mass = RHO0 * vol0
    x = ti.Vector.field(3, fp, n)
    v = ti.Vector.field(3, fp, n)
    C = ti.Matrix.field(3, 3, fp, n)
    vol = ti.field(fp, n)
    g_m = ti.field(fp, (nn, nn, nn))
    g_v = ti.Vector.field(3, fp, (nn, nn, nn))
    g_f = ti.Vector.field(3, fp, (nn, nn, nn))
    x.from_numpy(x0.astype(np.float64 if fp == ti.f64 else np.float32))
    vol.fill(vol0)
    inv_h = 1.0 / H
    gravity = ti.Vector(GRAVITY, fp)

    @ti.func
    def pressure(vp):
        rho = mass / vp
        return RHO0 * C_SOUND ** 2 / R_EOS * ((rho / RHO0) ** R_EOS - 1.0)

    @ti.func
    def slip_walls(I, vel):
        """Nodes on and beyond a face lose their velocity into the wall (geompm's slip wall)."""
        for a in ti.static(range(3)):
            if I[a] <= 0 and vel[a] < 0.0:
                vel[a] = 0.0
            if I[a] >= N_CELLS and vel[a] > 0.0:
                vel[a] = 0.0
        return vel

    @ti.kernel
    def step_usl():
        for I in ti.grouped(g_m):
            g_m[I] = 0.0
            g_v[I] = ti.Vector.zero(fp, 3)
            g_f[I] = ti.Vector.zero(fp, 3)
        for p in x:
            xi = x[p] * inv_h
            base = ti.cast(xi - 0.5, ti.i32)
            fx = xi - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
            dw = [(fx - 1.5) * inv_h, -2.0 * (fx - 1.0) * inv_h, (fx - 0.5) * inv_h]
            vsig = vol[p] * pressure(vol[p])  # -V sigma = V P I
            for i, j, k in ti.static(ti.ndrange(3, 3, 3)):
                off = ti.Vector([i, j, k])
                dpos = (off - fx) * H
                wt = w[i][0] * w[j][1] * w[k][2]
                grad = ti.Vector([dw[i][0] * w[j][1] * w[k][2], w[i][0] * dw[j][1] * w[k][2],
                                  w[i][0] * w[j][1] * dw[k][2]])
                g_m[base + off] += wt * mass
                g_v[base + off] += wt * mass * (v[p] + C[p] @ dpos)
                g_f[base + off] += vsig * grad
        for I in ti.grouped(g_m):
            if g_m[I] > 0.0:
                vel = g_v[I] / g_m[I] + DT * (g_f[I] / g_m[I] + gravity)
                g_v[I] = slip_walls(I, vel)
        for p in x:
            xi = x[p] * inv_h
            base = ti.cast(xi - 0.5, ti.i32)
            fx = xi - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
            dw = [(fx - 1.5) * inv_h, -2.0 * (fx - 1.0) * inv_h, (fx - 0.5) * inv_h]
            new_v = ti.Vector.zero(fp, 3)
            B = ti.Matrix.zero(fp, 3, 3)
            L = ti.Matrix.zero(fp, 3, 3)
            for i, j, k in ti.static(ti.ndrange(3, 3, 3)):
                off = ti.Vector([i, j, k])
                dpos = (off - fx) * H
                wt = w[i][0] * w[j][1] * w[k][2]
                grad = ti.Vector([dw[i][0] * w[j][1] * w[k][2], w[i][0] * dw[j][1] * w[k][2],
                                  w[i][0] * w[j][1] * dw[k][2]])
                gv = g_v[base + off]
                new_v += wt * gv
                B += wt * gv.outer_product(dpos)
                L += gv.outer_product(grad)
            v[p] = new_v
            C[p] = 4.0 * inv_h * inv_h * B
            x[p] += DT * new_v
            vol[p] *= (ti.Matrix.identity(fp, 3) + DT * L).determinant()

    @ti.kernel
    def step_mls():
        for I in ti.grouped(g_m):
            g_m[I] = 0.0
            g_v[I] = ti.Vector.zero(fp, 3)
        for p in x:
            xi = x[p] * inv_h
            base = ti.cast(xi - 0.5, ti.i32)
            fx = xi - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
            stress = DT * vol[p] * pressure(vol[p]) * 4.0 * inv_h * inv_h  # -dt V sigma D^-1
            affine = ti.Matrix.identity(fp, 3) * stress + mass * C[p]
            for i, j, k in ti.static(ti.ndrange(3, 3, 3)):
                off = ti.Vector([i, j, k])
                dpos = (off - fx) * H
                wt = w[i][0] * w[j][1] * w[k][2]
                g_m[base + off] += wt * mass
                g_v[base + off] += wt * (mass * v[p] + affine @ dpos)
        for I in ti.grouped(g_m):
            if g_m[I] > 0.0:
                vel = g_v[I] / g_m[I] + DT * gravity
                g_v[I] = slip_walls(I, vel)
        for p in x:
            xi = x[p] * inv_h
            base = ti.cast(xi - 0.5, ti.i32)
            fx = xi - base
            w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
            new_v = ti.Vector.zero(fp, 3)
            B = ti.Matrix.zero(fp, 3, 3)
            for i, j, k in ti.static(ti.ndrange(3, 3, 3)):
                off = ti.Vector([i, j, k])
                dpos = (off - fx) * H
                wt = w[i][0] * w[j][1] * w[k][2]
                gv = g_v[base + off]
                new_v += wt * gv
                B += wt * gv.outer_product(dpos)
            v[p] = new_v
            C[p] = 4.0 * inv_h * inv_h * B
            x[p] += DT * new_v
            vol[p] *= 1.0 + DT * C[p].trace()

    return (step_usl if scheme == "usl" else step_mls), x, v


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scheme", choices=["usl", "mls"], default="usl")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--threads", type=int, default=0, help="CPU threads (default: all cores)")
    ap.add_argument("--f32", action="store_true", help="single precision (geompm computes in float64)")
    args = ap.parse_args()
    fp = ti.f32 if args.f32 else ti.f64
    kw = {"cpu_max_num_threads": args.threads} if args.threads else {}
    ti.init(arch=ti.cpu, default_fp=fp, **kw)
    x0 = seed()
    step, x, v = build(x0, args.scheme, fp)
    step()
    step()
    ti.sync()
    t0 = time.perf_counter()
    for _ in range(args.steps):
        step()
    ti.sync()
    wall = time.perf_counter() - t0
    n = len(x0)
    ke = 0.5 * RHO0 * (H / PPC) ** 3 * float((v.to_numpy() ** 2).sum())
    print(f"taichi {ti.__version__} cpu {args.scheme} {'f32' if args.f32 else 'f64'}: {n} particles, "
          f"{args.steps} steps, {wall:.3f} s, {n * args.steps / wall:.4g} particle-steps/s, "
          f"mean y {float(x.to_numpy()[:, 1].mean()):.5f} m, kinetic energy {ke:.4e} J")


if __name__ == "__main__":
    main()
