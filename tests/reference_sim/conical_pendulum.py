#!/usr/bin/env python3
"""Independent reference simulator: ball on an inclined plate, tied to a fulcrum.

Standard library only (Python >= 3.11).  Used by the tests to produce a CSV
trajectory with known rolling-friction coefficient s_r, written in conventions
that deliberately differ from the project's own.

Model (ball radius r, mass m, solid sphere J_z = 2/5 m r^2, wire length d from
fulcrum to ball centre, plate inclined at alpha, psi = precession angle of the
wire in the plate, psi = 0 pointing downslope):

    sin(delta) = r/d,   L = sqrt(d^2 - r^2),   J_C = J_z + m r^2
    N   = J_C psi'^2 / r + m g (cos(alpha) + sin(alpha) tan(delta) cos(psi))
    M_r = s_r N^beta
    psi'' = -(m g r^2 sin(alpha) / (J_C L)) sin(psi) - (r M_r / (J_C L)) sgn(psi')

Energy view (used as a consistency check):
    KE = 1/2 J_C (L psi'/r)^2,  PE = -m g L sin(alpha) cos(psi),
    dissipated power P = M_r L |psi'| / r.

At a turning point (psi' = 0) the ball stays at rest for good if
    m g r sin(alpha) |sin(psi)| <= s_r N_static^beta,  N_static = N(psi, psi'=0),
otherwise it restarts towards psi = 0.

Numerics: classical fixed-step RK4 (default dt = 1e-3 s).  Each half swing is
integrated with sgn(psi') frozen (the ODE is smooth there); the step in which
psi' changes sign is shortened to the exact zero of psi', located by bisection
on the length of a single RK4 step from the step start.  Camera frames are
sampled by a single RK4 sub-step from the start of the step containing them.
The dissipated work W is integrated alongside as a third state variable, so
that E(t) + W(t) = E(0) can be checked.
"""

from __future__ import annotations

import argparse
import math
import random
import sys
import time

ANGLE_OFFSET_RAD = 1.9  # output angle = ANGLE_OFFSET_RAD - psi
EXTRA_NOTE = "ref"


class Model:
    def __init__(self, s_r, beta, d, r, m, alpha, g):
        if not (0.0 < r < d):
            raise ValueError("need 0 < r < d")
        self.s_r = float(s_r)
        self.beta = float(beta)
        self.d = float(d)
        self.r = float(r)
        self.m = float(m)
        self.alpha = float(alpha)
        self.g = float(g)
        self.sin_delta = r / d
        self.L = math.sqrt(d * d - r * r)
        self.tan_delta = r / self.L
        self.J_z = 0.4 * m * r * r
        self.J_C = self.J_z + m * r * r
        self.sin_a = math.sin(alpha)
        self.cos_a = math.cos(alpha)
        self.k_grav = m * g * r * r * self.sin_a / (self.J_C * self.L)
        self.k_fric = r / (self.J_C * self.L)

    # -- forces ------------------------------------------------------------
    def normal_force(self, psi, w):
        return self.J_C * w * w / self.r + self.m * self.g * (
            self.cos_a + self.sin_a * self.tan_delta * math.cos(psi))

    def rolling_torque(self, psi, w):
        if self.s_r == 0.0:
            return 0.0
        n = self.normal_force(psi, w)
        if n <= 0.0:
            return 0.0  # ball lifts off; cannot happen for sane parameters
        return self.s_r * n ** self.beta

    def stays_at_rest(self, psi):
        """Static check at a turning point (psi' = 0)."""
        drive = self.m * self.g * self.r * self.sin_a * abs(math.sin(psi))
        return drive <= self.rolling_torque(psi, 0.0)

    # -- energy ------------------------------------------------------------
    def energy(self, psi, w):
        v_rot = self.L * w / self.r
        return 0.5 * self.J_C * v_rot * v_rot - self.m * self.g * self.L * self.sin_a * math.cos(psi)

    def small_angle_period(self):
        return 2.0 * math.pi * math.sqrt(7.0 * self.L / (5.0 * self.g * self.sin_a))

    def exact_period(self, psi0):
        """Frictionless period for amplitude psi0 (AGM form of the elliptic integral)."""
        a, b = 1.0, math.cos(0.5 * psi0)
        for _ in range(60):
            a, b = 0.5 * (a + b), math.sqrt(a * b)
            if abs(a - b) < 1e-17:
                break
        omega0 = math.sqrt(self.k_grav)
        return 2.0 * math.pi / omega0 / a

    # -- ODE with frozen sign s = sgn(psi') ---------------------------------
    def deriv(self, psi, w, s):
        mr = self.rolling_torque(psi, w)
        acc = -self.k_grav * math.sin(psi) - self.k_fric * mr * s
        power = mr * self.L * (s * w) / self.r  # s*w = |psi'| within the half swing
        return w, acc, power

    def rk4(self, state, h, s):
        p, w, e = state
        k1p, k1w, k1e = self.deriv(p, w, s)
        hh = 0.5 * h
        k2p, k2w, k2e = self.deriv(p + hh * k1p, w + hh * k1w, s)
        k3p, k3w, k3e = self.deriv(p + hh * k2p, w + hh * k2w, s)
        k4p, k4w, k4e = self.deriv(p + h * k3p, w + h * k3w, s)
        h6 = h / 6.0
        return (p + h6 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p),
                w + h6 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w),
                e + h6 * (k1e + 2.0 * k2e + 2.0 * k3e + k4e))


class Result:
    def __init__(self):
        self.turns = []          # (t, psi) at each psi' = 0 after release
        self.t_stop = None       # time the ball came to rest for good
        self.samples = []        # psi at the requested frame times
        self.max_balance_err = 0.0  # max |E + W - E0| over step ends
        self.n_steps = 0


def simulate(model, psi0, t_end, dt, frame_times=(), max_turns=None, track_energy=False):
    """Integrate from rest at psi0 (t=0) until t_end (or max_turns turning points)."""
    res = Result()
    frames = list(frame_times)
    nf = len(frames)
    fi = 0
    t = 0.0
    state = (float(psi0), 0.0, 0.0)
    e0 = model.energy(psi0, 0.0)

    def emit(t0, st0, s, t1):
        nonlocal fi
        while fi < nf and frames[fi] <= t1:
            tau = frames[fi] - t0
            if tau <= 0.0:
                res.samples.append(st0[0])
            else:
                res.samples.append(model.rk4(st0, tau, s)[0])
            fi += 1

    def check_energy(st):
        err = abs(model.energy(st[0], st[1]) + st[2] - e0)
        if err > res.max_balance_err:
            res.max_balance_err = err

    done = False
    while not done and t < t_end:
        psi = state[0]
        if psi == 0.0 or model.stays_at_rest(psi):
            res.t_stop = t
            break
        s = -1.0 if psi > 0.0 else 1.0
        first = True
        h = dt
        while True:
            if t >= t_end:
                done = True
                break
            new = model.rk4(state, h, s)
            res.n_steps += 1
            if s * new[1] > 0.0:
                emit(t, state, s, t + h)
                t += h
                state = new
                if track_energy:
                    check_energy(state)
                first = False
                h = dt
                continue
            if first:
                # started from psi' = 0: shrink until the ball is visibly moving
                h *= 0.5
                if h < 1e-14:
                    raise RuntimeError("ball does not restart although static check failed")
                continue
            # psi' reaches 0 inside (0, h]: bisection on the RK4 step length
            lo, hi = 0.0, h
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                if s * model.rk4(state, mid, s)[1] > 0.0:
                    lo = mid
                else:
                    hi = mid
            tau = hi
            turn = model.rk4(state, tau, s)
            emit(t, state, s, t + tau)
            t += tau
            state = (turn[0], 0.0, turn[2])
            if track_energy:
                check_energy(state)
            res.turns.append((t, state[0]))
            if max_turns is not None and len(res.turns) >= max_turns:
                done = True
            break

    # ball at rest (or simulation ended): remaining frames keep the last angle
    while fi < nf:
        res.samples.append(state[0])
        fi += 1
    return res


# ---------------------------------------------------------------------------
def default_alpha_deg():
    return math.degrees(math.asin(0.142 / 1.5))


def model_from_args(a, s_r=None, beta=None):
    return Model(a.s_r if s_r is None else s_r, a.beta if beta is None else beta,
                 a.d, a.r, a.m, math.radians(a.alpha_deg), a.g)


def selftest(a):
    ok_all = True

    def report(name, ok, detail):
        nonlocal ok_all
        ok_all &= ok
        print(f"[{'PASS' if ok else 'FAIL'}] {name}: {detail}")

    dt = a.dt
    # 1. energy conservation without friction, 20 periods, psi0 = 10 deg
    mod = model_from_args(a, s_r=0.0)
    psi0 = math.radians(10.0)
    T = mod.exact_period(psi0)
    res = simulate(mod, psi0, 20.0 * T + 1.0, dt, max_turns=40, track_energy=True)
    e0 = mod.energy(psi0, 0.0)
    e_osc = mod.m * mod.g * mod.L * mod.sin_a * (1.0 - math.cos(psi0))
    rel_osc = res.max_balance_err / e_osc
    rel_tot = res.max_balance_err / abs(e0)
    report("energy conservation s_r=0, 20 periods", rel_osc < 1e-8 and len(res.turns) == 40,
           f"max|dE|/E_osc = {rel_osc:.3e}, max|dE|/|E0| = {rel_tot:.3e} (limit 1e-8)")

    # 2. frictionless period vs exact (elliptic) period at 10 deg
    t_period = res.turns[-1][0] / 20.0
    rel = abs(t_period - T) / T
    report("period vs exact elliptic period, psi0=10 deg", rel < 1e-9,
           f"T_sim = {t_period:.12f} s, T_exact = {T:.12f} s, rel = {rel:.3e} (limit 1e-9)")

    # 3. small-angle period, psi0 = 0.5 deg
    psi0s = math.radians(0.5)
    res = simulate(mod, psi0s, 1e9, dt, max_turns=2)
    t_sim = res.turns[1][0]
    t0 = mod.small_angle_period()
    rel = abs(t_sim - t0) / t0
    report("small-angle period 2*pi*sqrt(7L/(5 g sin a)), psi0=0.5 deg", rel < 1e-4,
           f"T_sim = {t_sim:.9f} s, T_formula = {t0:.9f} s, rel = {rel:.3e} (limit 1e-4)")

    # 4. energy balance with friction (E + W = E0), default parameters
    modf = model_from_args(a)
    psi0d = math.radians(a.psi0_deg)
    res = simulate(modf, psi0d, a.duration, dt, track_energy=True)
    e_osc = modf.m * modf.g * modf.L * modf.sin_a * (1.0 - math.cos(psi0d))
    rel = res.max_balance_err / e_osc
    report("energy balance E + W_dissipated = E0 with friction", rel < 1e-8,
           f"max|E+W-E0|/E_osc = {rel:.3e} over {len(res.turns)} half swings (limit 1e-8)")

    # 5. step-size convergence of the turning amplitudes (dt vs dt/2)
    res2 = simulate(modf, psi0d, a.duration, 0.5 * dt)
    n = min(len(res.turns), len(res2.turns))
    dmax = max(abs(x[1] - y[1]) for x, y in zip(res.turns[:n], res2.turns[:n]))
    tmax = max(abs(x[0] - y[0]) for x, y in zip(res.turns[:n], res2.turns[:n]))
    report("turning amplitudes dt vs dt/2", n > 0 and len(res.turns) == len(res2.turns) and dmax < 1e-9,
           f"{n} turns, max |d psi| = {dmax:.3e} rad, max |d t| = {tmax:.3e} s (limit 1e-9 rad)")

    # 6. beta = 0 (constant torque s_r): turning amplitudes have a closed-form
    #    recurrence m g L sin(a) (cos A_{n+1} - cos A_n) = (s_r L / r)(A_n + A_{n+1})
    c = 0.003  # friction angle: s_r / (m g r sin a), i.e. ~2c rad lost per half swing
    s0 = c * modf.m * modf.g * modf.r * modf.sin_a
    mod0 = Model(s0, 0.0, a.d, a.r, a.m, math.radians(a.alpha_deg), a.g)
    res = simulate(mod0, psi0d, 1e9, dt)
    amp = psi0d
    errs = []
    for (_, p) in res.turns:
        x = amp - 2.0 * c  # Newton (x = -amp is a spurious root)
        # Newton on f(x) = cos x - cos amp - c (amp + x)
        for _ in range(50):
            f = math.cos(x) - math.cos(amp) - c * (amp + x)
            x -= f / (-math.sin(x) - c)
        errs.append(abs(abs(p) - x))
        amp = abs(p)
    # stop condition: final amplitude must satisfy |sin A| <= c, previous must not
    stop_ok = (res.t_stop is not None and abs(math.sin(amp)) <= c
               and (len(res.turns) < 2 or abs(math.sin(abs(res.turns[-2][1]))) > c))
    emax = max(errs) if errs else float("inf")
    report("beta=0 closed-form turning amplitudes + stop rule", emax < 1e-9 and stop_ok,
           f"{len(res.turns)} turns, max err = {emax:.3e} rad, stopped at t = {res.t_stop}, "
           f"final |psi| = {math.degrees(amp):.6f} deg (static limit asin(c) = {math.degrees(math.asin(c)):.6f} deg)")

    print("SELFTEST " + ("PASS" if ok_all else "FAIL"))
    return 0 if ok_all else 1


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--s-r", type=float, default=4.508e-6, help="rolling friction coefficient s_r (m)")
    p.add_argument("--beta", type=float, default=1.0, help="exponent on N")
    p.add_argument("--d", type=float, default=0.2276, help="wire length, fulcrum to ball centre (m)")
    p.add_argument("--r", type=float, default=0.03175, help="ball radius (m)")
    p.add_argument("--m", type=float, default=1.0458, help="ball mass (kg)")
    p.add_argument("--alpha-deg", type=float, default=default_alpha_deg(), help="plate inclination (deg)")
    p.add_argument("--g", type=float, default=9.81, help="gravity (m/s^2)")
    p.add_argument("--psi0-deg", type=float, default=10.0, help="release angle, from rest at t=0 (deg)")
    p.add_argument("--duration", type=float, default=90.0, help="length of the recording (s)")
    p.add_argument("--fps", type=float, default=30.0, help="camera frame rate (1/s)")
    p.add_argument("--noise-deg", type=float, default=0.0, help="Gaussian angle noise sigma (deg)")
    p.add_argument("--seed", type=int, default=7, help="noise RNG seed")
    p.add_argument("--dt", type=float, default=1e-3, help="RK4 step (s)")
    p.add_argument("-o", "--output", help="output CSV path ('-' for stdout)")
    p.add_argument("--selftest", action="store_true", help="run the self checks and exit")
    a = p.parse_args(argv)

    if a.selftest:
        return selftest(a)
    if not a.output:
        p.error("-o OUTPUT.csv is required (or --selftest)")

    t_wall = time.process_time()
    model = model_from_args(a)
    n_frames = int(math.floor(a.duration * a.fps + 1e-9)) + 1
    frame_times = [k / a.fps for k in range(n_frames)]
    res = simulate(model, math.radians(a.psi0_deg), a.duration, a.dt, frame_times)

    rng = random.Random(a.seed)
    sigma = math.radians(a.noise_deg)
    lines = ["frame,t_s,angle_rad,extra_note"]
    for k, (tf, psi) in enumerate(zip(frame_times, res.samples)):
        ang = ANGLE_OFFSET_RAD - psi
        if sigma > 0.0:
            ang += rng.gauss(0.0, sigma)
        lines.append(f"{k},{tf!r},{ang:.12f},{EXTRA_NOTE}")
    text = "\n".join(lines) + "\n"
    if a.output == "-":
        sys.stdout.write(text)
    else:
        with open(a.output, "w", newline="") as fh:
            fh.write(text)

    first = (f"{math.degrees(abs(res.turns[0][1])):.6f} deg at t={res.turns[0][0]:.6f} s"
             if res.turns else "none")
    stop = f"{res.t_stop:.6f} s" if res.t_stop is not None else "did not stop"
    print(f"half_swings={len(res.turns)} stopped={stop} first_turning_amplitude={first} "
          f"frames={n_frames} cpu={time.process_time() - t_wall:.2f}s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
