"""Modified Cam-Clay (Roscoe & Burland 1968): a clay whose elastic region is an ellipse that grows as it compacts.

With p the mean effective stress (compression positive), q = sqrt(3 J2), M the critical stress ratio and p_c the
preconsolidation pressure (Roscoe & Burland 1968, in Engineering Plasticity, Cambridge UP, pp. 535-609; Wood
1990, Soil Behaviour and Critical State Soil Mechanics, ch. 4-7):

    f = q^2 / M^2 + p (p - p_c) <= 0,          associated flow: d eps_v^p = dl (2 p - p_c),  d eps_q^p = dl 2 q / M^2
    elastic:    d eps_v^e = kappa* dp / p,      G = 3 (1 - 2 nu) / (2 (1 + nu)) p / kappa*
    hardening:  d p_c / p_c = d eps_v^p / (lambda* - kappa*)

(eps_v compression positive).  The indices are those of the log-log form, lambda* = lambda / (1 + e0) and
kappa* = kappa / (1 + e0) (Butterfield 1979, Geotechnique 29(4):469), lambda and kappa the slopes of the normal
compression and swelling lines in e - ln p' and e0 the initial void ratio: the specific volume in the moduli is
held at its initial value, as in Borja & Lee (1990, CMAME 78:49).  M = 6 sin(phi_cs) / (3 - sin(phi_cs)), the
triaxial-compression match to the critical friction angle.

The return is implicit (backward Euler in p, q and p_c, with p and p_c integrated exactly in their logarithms):
for the plastic multiplier dl the trial stress (p_tr, q_tr) returns to

    p = p_tr exp(-x / kappa*),  p_c = p_c,n exp(x / (lambda* - kappa*)),  q = q_tr / (1 + 6 G dl / M^2),
    x = dl (2 p - p_c)   (the plastic volumetric strain increment),   f(p, q, p_c) = 0,

solved by a bracketed Newton iteration on dl with an inner Newton on x (both to round-off).  Every returned
state then satisfies the yield condition and the exact relations between ln p, ln p_c and the volumetric strains,
so the closed-form stress paths (undrained: p / p0 = (M^2 / (M^2 + eta^2))^(1 - kappa*/lambda*); drained:
eps_v = kappa* ln(p / p0) + (lambda* - kappa*) ln(p (M^2 + eta^2) / (M^2 p_c0))) hold at every step whatever
its size.  Below ``minimum_mean_stress`` the bulk modulus is held at its value there (a particle at the free
surface keeps a stiffness), and a particle stretched to zero mean stress separates, stress-free.

State variables: the equivalent plastic shear strain eps_q^p, the plastic volumetric strain (dilatant positive, as
the other laws), and p_c [Pa].  A particle starts with p_c = max(OCR p_eq, preconsolidation_pressure) where
p_eq = p + q^2 / (M^2 p) is the ellipse through its initial stress (set at its first step).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from pydantic import Field, model_validator

from geompm.contract.layout import param_layout
from geompm.materials.base import Material, MaterialParams
from geompm.materials.plasticity import elastic_trial, sqrt_j2
from geompm.materials.plausible import DENSITY, Plausible, angle

#: packed parameters: rho0 [kg/m3], M [-], lambda* and kappa* [-], the shear-to-bulk modulus ratio [-], the
#: overconsolidation ratio [-], the given preconsolidation pressure [Pa] (0: none), the smallest mean stress of
#: the bulk modulus [Pa], the mean stress at which the wave speed is taken [Pa]
MCC = param_layout("density", "M", "lam_star", "kap_star", "g_ratio", "ocr", "pc_given", "p_min", "p_wave")

SQ3 = math.sqrt(3.0)


class ModifiedCamClayParams(MaterialParams):
    poisson_ratio: float = Field(ge=0.0, lt=0.5, description="Poisson's ratio nu [-] (G from the bulk modulus)")
    critical_friction_angle: float = Field(
        gt=0.0, lt=90.0, description="Friction angle at the critical state phi_cs [deg]; M = 6 sin(phi_cs) / "
        "(3 - sin(phi_cs))")
    compression_index: float = Field(gt=0.0, description="lambda [-]: slope of the normal compression line in "
                                                         "e - ln p'")
    swelling_index: float = Field(gt=0.0, description="kappa [-]: slope of the swelling line in e - ln p'")
    void_ratio: float = Field(gt=0.0, description="Initial void ratio e0 [-]")
    overconsolidation_ratio: float = Field(
        1.0, ge=1.0, description="OCR [-]: p_c over the initial ellipse's p_eq = p + q^2 / (M^2 p) of each "
        "particle (1: normally consolidated)")
    preconsolidation_pressure: float | None = Field(
        None, gt=0.0, description="A preconsolidation pressure p_c [Pa] for every particle (the larger of it and "
        "OCR p_eq is taken)")
    minimum_mean_stress: float = Field(
        1000.0, gt=0.0, description="Mean stress [Pa] below which the bulk modulus is held at p_min / kappa*")
    stiffness_pressure: float | None = Field(
        None, gt=0.0, description="Mean stress [Pa] at which the wave speed of the time step is taken; default "
        "four times the largest initial preconsolidation pressure")

    @model_validator(mode="after")
    def _indices(self):
        if self.swelling_index >= self.compression_index:
            raise ValueError(f"swelling_index {self.swelling_index:g} must be below compression_index "
                             f"{self.compression_index:g} (the clay must harden as it compacts)")
        return self

    def m_ratio(self) -> float:
        s = math.sin(math.radians(self.critical_friction_angle))
        return 6.0 * s / (3.0 - s)


@njit(cache=True, inline="always")
def _elastic_p(p_n, de, kap, p_min):
    """(p, dp/dde) after the elastic volumetric strain de (compression positive) from p_n."""
    if p_n >= p_min:
        p = p_n * math.exp(de / kap)
        return p, p / kap
    return p_n + p_min * de / kap, p_min / kap


@njit(cache=True, inline="always")
def _inner(dl, p_n, dev, pc_n, kap, hard, p_min):
    """x (plastic volumetric strain) solving x = dl (2 p(x) - p_c(x)), with p, p_c and their x-derivatives."""
    x = 0.0
    cap = 0.5 * min(kap, hard)
    for _ in range(100):
        p, kp = _elastic_p(p_n, dev - x, kap, p_min)
        pc = pc_n * math.exp(x / hard)
        g = x - dl * (2.0 * p - pc)
        dg = 1.0 + dl * (2.0 * kp + pc / hard)
        step = g / dg
        step = max(-cap, min(cap, step))
        x -= step
        if abs(step) <= 1e-15 * (1.0 + abs(x)):
            break
    p, kp = _elastic_p(p_n, dev - x, kap, p_min)
    pc = pc_n * math.exp(x / hard)
    return x, p, kp, pc, 1.0 + dl * (2.0 * kp + pc / hard)


@njit(cache=True, inline="always")
def _yield(dl, q_tr, c6, M2, p_n, dev, pc_n, kap, hard, p_min):
    """(f, df/ddl, x, p, q, p_c) at the multiplier dl."""
    x, p, kp, pc, dg = _inner(dl, p_n, dev, pc_n, kap, hard, p_min)
    den = 1.0 + c6 * dl
    q = q_tr / den
    dx = (2.0 * p - pc) / dg
    f = q * q / M2 + p * (p - pc)
    df = -2.0 * q * q * c6 / (den * M2) + (-(2.0 * p - pc) * kp - p * pc / hard) * dx
    return f, df, x, p, q, pc


@njit(cache=True, inline="always")
def initial_preconsolidation(prm, s):
    """p_c [Pa] of a particle at its initial effective stress s (Voigt): max(OCR p_eq, the given p_c, p_min) with
    p_eq = p + q^2 / (M^2 p) the ellipse through s (0 where p <= 0)."""
    mean = (s[0] + s[1] + s[2]) / 3.0
    q = SQ3 * sqrt_j2(s, mean)
    p = -mean
    peq = p + q * q / (prm[MCC.M] * prm[MCC.M] * p) if p > 0.0 else 0.0
    return max(prm[MCC.ocr] * peq, prm[MCC.pc_given], prm[MCC.p_min])


@njit(cache=True)
def initial_preconsolidations(prm, stress, out):
    """initial_preconsolidation of each row of stress (n, 6) into out (n,)."""
    for i in range(stress.shape[0]):
        out[i] = initial_preconsolidation(prm, stress[i])


@njit(cache=True)
def mcc_stress(prm, dt, L, rho, s, state):
    """One particle's Modified Cam-Clay return (module docstring); s (6,) and state (3,) in place."""
    M = prm[MCC.M]
    M2 = M * M
    kap, hard = prm[MCC.kap_star], prm[MCC.lam_star] - prm[MCC.kap_star]
    p_min = prm[MCC.p_min]
    mean_n = (s[0] + s[1] + s[2]) / 3.0
    p_n = -mean_n
    if state[2] <= 0.0:  # first step: the ellipse through the initial stress, times OCR, or the given p_c
        state[2] = initial_preconsolidation(prm, s)
    G = prm[MCC.g_ratio] * max(p_n, p_min) / kap
    tr = elastic_trial(s, L, dt, -2.0 * G / 3.0, G)  # the deviator's trial; its mean is still mean_n
    dev = -(L[0, 0] + L[1, 1] + L[2, 2]) * dt  # volumetric strain increment, compression positive
    p_tr, _ = _elastic_p(max(p_n, 0.0), dev, kap, p_min)
    if p_tr <= 0.0:  # stretched past zero mean stress: separated, stress-free
        for i in range(6):
            s[i] = 0.0
        return
    q_tr = SQ3 * sqrt_j2(tr, mean_n)
    pc_n = state[2]
    if q_tr * q_tr / M2 + p_tr * (p_tr - pc_n) <= 0.0:
        scale, p = 1.0, p_tr
    else:
        c6 = 6.0 * G / M2
        lo, hi = 0.0, 1.0 / (c6 + 1e-300)
        for _ in range(200):  # bracket: f(hi) < 0
            if _yield(hi, q_tr, c6, M2, max(p_n, 0.0), dev, pc_n, kap, hard, p_min)[0] < 0.0:
                break
            lo, hi = hi, 2.0 * hi
        dl = 0.5 * (lo + hi)
        tol = 1e-14 * pc_n * pc_n
        x, p, q, pc = 0.0, p_tr, q_tr, pc_n
        for _ in range(200):
            f, df, x, p, q, pc = _yield(dl, q_tr, c6, M2, max(p_n, 0.0), dev, pc_n, kap, hard, p_min)
            if abs(f) <= tol:
                break
            if f > 0.0:
                lo = dl
            else:
                hi = dl
            nxt = dl - f / df if df != 0.0 else 0.5 * (lo + hi)
            if not (lo < nxt < hi):
                nxt = 0.5 * (lo + hi)
            if hi - lo <= 1e-16 * hi:
                break
            dl = nxt
        scale = q / q_tr if q_tr > 0.0 else 0.0
        state[0] += dl * 2.0 * q / M2
        state[1] -= x
        state[2] = pc
    for i in range(3):
        s[i] = (tr[i] - mean_n) * scale - p
    for i in range(3, 6):
        s[i] = tr[i] * scale


@njit(cache=True)
def mcc_wave_speed(prm, rho):
    """P-wave speed sqrt((K + 4 G / 3) / rho) [m/s] at the mean stress ``stiffness_pressure``."""
    K = prm[MCC.p_wave] / prm[MCC.kap_star]
    return math.sqrt(K * (1.0 + 4.0 / 3.0 * prm[MCC.g_ratio]) / rho)


class ModifiedCamClay(Material):
    name = "modified_cam_clay"
    backends = ("cpu", "cuda")  # same numbers as the CPU under the simulator (tests/cuda/cuda_parity.py); compiles for sm_90 (tests/cuda/cuda_compile.py)
    description = "Modified Cam-Clay clay (Roscoe & Burland 1968): elliptical yield, hardening with compaction"
    Params = ModifiedCamClayParams
    state_vars = ("plastic_strain", "plastic_volumetric_strain", "preconsolidation_pressure")
    layout = MCC
    particle_stress = mcc_stress
    particle_wave_speed = mcc_wave_speed
    plausible = (DENSITY, angle("critical_friction_angle"),
                 Plausible("compression_index", high=2.0, hint=lambda v: (
                     f"above 2: clays measure lambda = 0.05-0.5 (an index, not a percentage or a Cc = 2.303 "
                     f"lambda: Cc {v:g} is lambda {v / 2.303:.3g})")),
                 Plausible("preconsolidation_pressure", low=100.0, hint=lambda v: (
                     f"below 100 Pa: was it given in kPa? ({v:g} kPa is {v * 1e3:g} Pa)")))

    def __init__(self, params):
        super().__init__(params)
        self._p_wave_given = params.stiffness_pressure is not None
        self._p_typical = self.prm[MCC.p_wave] / 4.0  # the initial mean stress's median, once known

    @classmethod
    def pack(cls, p):
        nu = p.poisson_ratio
        pc = 0.0 if p.preconsolidation_pressure is None else p.preconsolidation_pressure
        p_wave = p.stiffness_pressure or 4.0 * max(pc, p.minimum_mean_stress)
        return {"density": p.density, "M": p.m_ratio(), "lam_star": p.compression_index / (1.0 + p.void_ratio),
                "kap_star": p.swelling_index / (1.0 + p.void_ratio),
                "g_ratio": 3.0 * (1.0 - 2.0 * nu) / (2.0 * (1.0 + nu)), "ocr": p.overconsolidation_ratio,
                "pc_given": pc, "p_min": p.minimum_mean_stress, "p_wave": p_wave}

    @classmethod
    def example_params(cls):
        return cls.Params(density=1800.0, poisson_ratio=0.3, critical_friction_angle=25.0, compression_index=0.2,
                          swelling_index=0.04, void_ratio=1.0, overconsolidation_ratio=1.2)

    def start_preconsolidation(self, stress: np.ndarray) -> np.ndarray:
        """Each particle's p_c at its first step from its initial effective stress (n, 6): the kernel's own
        initial_preconsolidation."""
        out = np.empty(len(stress))
        initial_preconsolidations(self.prm, np.ascontiguousarray(stress, dtype=float), out)
        return out

    def initial_stress_checks(self, stress: np.ndarray) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
        """(problems, warnings) as (field, sentence) for the block's initial effective stress; sets the wave
        speed's mean stress to four times the largest initial p_c unless stiffness_pressure is given."""
        p = self.params
        problems, warnings = [], []
        if len(stress) == 0:
            return problems, warnings
        pc = self.start_preconsolidation(stress)
        if not self._p_wave_given:
            self.prm[MCC.p_wave] = 4.0 * float(pc.max())
        mean = -stress[:, :3].mean(axis=1)
        self._p_typical = max(float(np.median(mean)), p.minimum_mean_stress)
        if p.preconsolidation_pressure is not None and p.overconsolidation_ratio == 1.0 and \
                (mean > p.preconsolidation_pressure).any():
            warnings.append(("preconsolidation_pressure", f"{p.preconsolidation_pressure:g} Pa is below the initial "
                             f"mean effective stress of {int((mean > p.preconsolidation_pressure).sum())} particles "
                             f"(up to {mean.max():.4g} Pa): they start on their own normally consolidated ellipse "
                             "(OCR 1) instead; raise it or give overconsolidation_ratio"))
        e_top = p.void_ratio - p.compression_index * math.log(10.0)
        if e_top <= 0.0:
            problems.append(("compression_index", f"{p.compression_index:g} with void_ratio {p.void_ratio:g} gives a "
                             f"negative void ratio ({e_top:.3g}) on the normal compression line within a decade of "
                             f"stress above the initial state (up to {10 * pc.max():.4g} Pa): check both"))
        return problems, warnings

    def k0(self) -> float:
        """Jaky (1944), K0 = 1 - sin(phi_cs)."""
        return 1.0 - math.sin(math.radians(self.params.critical_friction_angle))

    def stiffness(self) -> float:
        """Young's modulus [Pa] at the median initial mean stress (at least p_min): a typical one, for
        artificial damping and the energy check's strain energy sigma^2 / (2 E), which it then does not
        underestimate for a block whose stresses spread from 0 to twice the median."""
        K = self._p_typical / self.prm[MCC.kap_star]
        return float(3.0 * K * (1.0 - 2.0 * self.params.poisson_ratio))
