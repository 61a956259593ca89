"""Lumped electro-thermal battery pack (battery-models.md §2.2, §3.3, §4).

Per cell (I > 0 = charge, T in °C, s = stored charge / capacity):

    eta   = 1 - exp(-(1 - s) / (w0 * (1 + wT * (T - 25))))      on charge, 1 on discharge
    ds/dt = eta * I / (3600 * Q)
    f(T)  = exp(Ea / Rgas * (1 / (T + 273.15) - 1 / 298.15))   scales R0, R1, R2
    Rpol  = k_d / (s + eps) on discharge   (Tremblay knee, instantaneous)
    Vp    = min(Vp * a_p + I * k_c / (1 - s + eps) * (1 - a_p), Vp_max) on charge, Vp * a_p otherwise
            (Tremblay charge polarisation through an RC: a lead-acid cell's surface charge relaxes
             over minutes, and gassing caps it)
    Vk    = Vk * a_k + I * Rk * f * (1 - a_k),   a_k = exp(-dt / tau_k)   (exact for constant I)
    x     = x * a_x + eta * I * dt / (3600 * Q) * (tau_x / dt) * (1 - a_x),   a_x = exp(-dt / tau_x)
    E     = U(s + x) - kT * (T - 25)
    D     = k_dip * o * a_o,   a_o = exp(-dt / tau_dip)
    V     = E + (1 - eta) * dV_O2 [charge only] - D + I * (R0 * f + Rpol) + V1 + V2 + Vp
    q     = I * (V - eta * E) + eta * I * q_rev     (all input power not stored as chemistry is heat)
    Cth * dT/dt = q - hA * (T - T_amb)       (stepped exactly for q held over the step)
    o     = o * a_o + (1 - eta) * I * dt / (3600 * Q) [charge only]
    L     = L + (1 - eta) * I * dt / (3600 * Q) on charge, max(0, L + I * dt / (3600 * Q)) on discharge
    V    += k_over * L^2
    V    -= M * (1 - h) / 2
    h     = sgn(I) + (h - sgn(I)) * exp(-|I| * dt / (3600 * Q * q_h))     (while I != 0)

x is solid-state diffusion (lithium): how far the particles' surface, where the OCV is read, is ahead of
their bulk s. It lags the current with tau_x (`diffusion_tau_s`) and under a steady current settles at the
charge of tau_x seconds: a single particle's surface leads its mean by R^2/(15 D) seconds of current, so
tau_x = R^2/(15 D) (the steady gain of Fick's law in a sphere). In CV the surface reaches the full end of the
steep OCV first and the current falls as the bulk catches up: the tail's shape follows the OCV's curvature,
which no RC pair's linear overvoltage does. tau_x = 0: no diffusion (x stays 0).

h is where the cell stands between its OCV branches (Plett's one-state hysteresis): +1 on the charge
branch, the OCV table (fitted on charges), -1 on the discharge branch, M lower; charge moves it towards
+1 and discharge towards -1, e-fold over q_h of the capacity. A pack starts on its charge branch. M is
zero where the data show no hysteresis (everything but NiMH): those runs are unchanged. Like D, the step
uses h before this step's, so the CV solve sees a constant.

L is the overcharge a lithium cell took past full (no O2 cycle takes it up: it plates lithium and
oxidises the electrolyte); its voltage climbs ever more steeply with it (k_over at a capacity's worth),
so a charge that nothing stops shows as one: 4.2 V at full, about 4.45 V at 130 % and 4.9 V at 150 %
for LiPo. Squared, the few tenths of a percent a normal CV tail leaves unaccepted add nothing. A
discharge takes it back first. Like D, the step uses L before this step's.

o is the overcharge (the charge the O2 cycle took, as a fraction of the capacity) that has not yet
relaxed: the oxygen it makes depolarises the negative electrode, so past the peak the voltage falls
by D however little the pack heats (the NiCd/NiMH -dV). It relaxes with tau_dip, so in a long
overcharge the dip levels off at k_dip * C-rate * tau_dip / 3600: deeper at a higher rate. D uses
the overcharge before this step's: the terminal voltage then rises with the current, as the CV
solve needs (a dip that deepened within the step could make it fall).

`step` is the simulator's hot loop: the constants live in one tuple built in
``__init__`` (and re-built only when dt changes) so each step is plain float
arithmetic on locals.
"""
from __future__ import annotations

from bisect import bisect_right
from math import exp, isfinite

from ..domain.chemistry import Chemistry
from ..i18n import _

_GAS_R = 8.314462618          # J/(mol K), physical constant
_T_REF_K = 298.15             # parameters are given at 25 °C
_T_REF_C = 25.0
_KELVIN = 273.15
_W_FLOOR = 0.05               # keeps the acceptance width positive in deep cold (w_t * (T - 25) -> -1)
# Past empty a cell's voltage collapses (its reversal region): the OCV falls this much per unit of
# charge taken beyond s = 0, so a discharge that nothing stops drives the cell towards 0 V.
_COLLAPSE_V_PER_SOC = 20.0
_SOC_FLOOR = -0.06
# The ambient temperatures the model is meant for (and a charger works in); the simulator's
# form, `zuml simulate --ambient` and the virtual charger take these.
AMBIENT_MIN_C, AMBIENT_MAX_C = -20.0, 60.0


def ambient_error(value: float) -> str:
    return _("ambient temperature {value:g} °C: the model covers {low:g} to {high:g} °C").format(
        value=value, low=AMBIENT_MIN_C, high=AMBIENT_MAX_C)


class Pack:
    """`series` identical cells in series; parameters scaled to `capacity_mah` (R ∝ 1/capacity, heat capacity and heat-loss ∝ capacity).

    ``r_scale`` multiplies the resistances (a cell of a pack of unequal cells, `sim/cell_pack.py`)."""

    per_cell = False      # one state for every cell: the cells' voltages are voltage / series
    # What `step` carries from tick to tick: the C engine (sim/engine.py) copies it in and back.
    STATE = ("soc", "temp_c", "current", "cell_voltage", "voltage", "_v1", "_v2", "_vp", "_oc", "_over", "_h",
             "_surf")

    def __init__(self, chem: Chemistry, capacity_mah: float, series: int, soc: float = 0.0,
                 ambient_c: float = 25.0, r_scale: float = 1.0) -> None:
        if not (capacity_mah > 0 and isfinite(capacity_mah)) or series < 1:
            raise ValueError(_("capacity_mah must be > 0 and series >= 1"))
        if not AMBIENT_MIN_C <= ambient_c <= AMBIENT_MAX_C:
            raise ValueError(ambient_error(ambient_c))
        self.chem = chem
        self.capacity_mah = float(capacity_mah)
        self.series = int(series)
        self.soc = min(1.0, max(0.0, float(soc)))
        self.ambient_c = float(ambient_c)
        self.temp_c = float(ambient_c)
        self.current = 0.0
        self._v1 = 0.0
        self._v2 = 0.0
        self._vp = 0.0
        self._oc = 0.0
        self._over = 0.0
        self._h = 1.0
        self._surf = 0.0      # x: the particles' surface ahead of their bulk (state of charge)

        q_ah = self.capacity_mah / 1000.0
        scale_r = chem.ref_capacity_ah / q_ah * r_scale    # R x Ah is constant within a family [N11]
        scale_th = q_ah / chem.ref_capacity_ah
        self._q_as = 3600.0 * q_ah
        self._r0 = chem.r0_ohm * scale_r
        self._r1 = chem.r1_ohm * scale_r
        self._r2 = chem.r2_ohm * scale_r
        self._kc = chem.k_charge_ohm * scale_r
        self._kd = chem.k_discharge_ohm * scale_r
        self._cth = chem.cth_j_per_k * scale_th
        self._ha = chem.ha_w_per_k * scale_th
        self._xs = chem.ocv_soc
        self._ys = chem.ocv_v
        self._slopes = tuple((y1 - y0) / (x1 - x0) for x0, x1, y0, y1
                             in zip(self._xs, self._xs[1:], self._ys, self._ys[1:]))
        self._dt = -1.0
        self._k: tuple = ()
        # The constants per tick length: a fit drives the model along a decimated log whose steps alternate
        # between a few lengths, and recomputing them at each change was a third of a fit's time.
        self._k_by_dt: dict[float, tuple] = {}
        self._set_dt(1.0)
        self.cell_voltage = self._cell_ocv()
        self.voltage = self.cell_voltage * self.series

    # -- constants -------------------------------------------------------
    def _set_dt(self, dt: float) -> None:
        self._dt = dt
        known = self._k_by_dt.get(dt)
        if known is not None:
            self._k = known
            return
        c = self.chem
        a1 = exp(-dt / c.tau1_s)
        a2 = exp(-dt / c.tau2_s)
        a_x = exp(-dt / c.diffusion_tau_s) if c.diffusion_tau_s > 0.0 else 0.0
        self._dt = dt
        self._k = (
            self._r0, self._r1 * (1.0 - a1), a1, self._r2 * (1.0 - a2), a2,
            c.ea_j_per_mol / _GAS_R, c.ea_j_per_mol / _GAS_R / _T_REF_K, self._kc, self._kd, c.pol_eps,
            1.0 / c.w0, c.w_t_per_k, c.dv_o2_v, c.k_t_v_per_k, c.q_rev_v,
            dt / self._q_as, exp(-dt * self._ha / self._cth), 1.0 / self._ha,
            self._xs, self._ys, self._slopes, len(self._xs) - 1, self.series,
            exp(-dt / c.pol_tau_s), c.pol_max_v,
            c.dip_v_per_charge, exp(-dt / c.dip_tau_s), c.overcharge_v_per_charge,
            0.5 * c.hyst_v, dt / (self._q_as * c.hyst_soc),
            a_x, c.diffusion_tau_s / dt * (1.0 - a_x),
        )
        self._k_by_dt[dt] = self._k

    def _cell_ocv(self) -> float:
        """U(soc) at the present temperature, per cell."""
        xs, s = self._xs, self.soc + self._surf
        if s < 0.0:
            u = self._ys[0] + s * _COLLAPSE_V_PER_SOC
        else:
            j = min(bisect_right(xs, s), len(xs) - 1)
            u = self._ys[j - 1] + (s - xs[j - 1]) * self._slopes[j - 1]
        return u - self.chem.k_t_v_per_k * (self.temp_c - _T_REF_C)

    # -- public API ------------------------------------------------------
    def step_constants(self, dt: float) -> tuple:
        """`step`'s constants at a tick of dt, in their order (the C engine's pack takes them)."""
        if dt != self._dt:
            self._set_dt(dt)
        return self._k

    def open_circuit_voltage(self) -> float:
        """Pack voltage at zero current now: U(s) with its temperature term plus the RC voltages
        that have not relaxed yet, i.e. what a charger reads when it switches its power stage off."""
        return (self._cell_ocv() + self._v1 + self._v2 + self._vp - self._dip()
                + self.chem.overcharge_v_per_charge * self._over * self._over
                - 0.5 * self.chem.hyst_v * (1.0 - self._h)) * self.series

    def _dip(self) -> float:
        return self.chem.dip_v_per_charge * self._oc

    def step(self, current_a: float, dt: float) -> float:
        """Advance dt seconds at `current_a` (+ = charge); returns the pack terminal voltage."""
        if dt != self._dt:
            self._set_dt(dt)
        (r0, r1b, a1, r2b, a2, ea_r, ea_r_ref, kc, kd, eps, inv_w0, w_t, dv_o2, k_t, q_rev,
         ds_k, a_th, inv_ha, xs, ys, slopes, last, series, a_p, vp_max, k_dip, a_o, k_over, half_m, h_k, a_x,
         b_x) = self._k
        i = current_a
        s = self.soc
        t = self.temp_c
        f = exp(ea_r / (t + _KELVIN) - ea_r_ref)
        vp = self._vp * a_p
        if i > 0.0:
            wf = 1.0 + w_t * (t - _T_REF_C)
            if wf < _W_FLOOR:
                wf = _W_FLOOR
            eta = 1.0 - exp((s - 1.0) * inv_w0 / wf)
            r = r0 * f
            vp += i * kc / (1.0 - s + eps) * (1.0 - a_p)
            if vp > vp_max:
                vp = vp_max
            extra = (1.0 - eta) * dv_o2
            oc = self._oc * a_o + (1.0 - eta) * i * ds_k
            over = self._over + (1.0 - eta) * i * ds_k
        else:
            oc = self._oc * a_o
            over = self._over + i * ds_k
            if over < 0.0:
                over = 0.0
            eta = 1.0
            r = r0 * f + kd / ((s if s > 0.0 else 0.0) + eps)
            extra = 0.0
        v1 = self._v1 * a1 + i * r1b * f
        v2 = self._v2 * a2 + i * r2b * f
        ds = eta * i * ds_k
        x = self._surf * a_x + ds * b_x
        s += ds
        if s > 1.0:
            s = 1.0
        elif s < _SOC_FLOOR:
            s = _SOC_FLOOR
        su = s + x      # the surface, where the OCV is read
        if su < 0.0:
            if su < _SOC_FLOOR:
                su = _SOC_FLOOR
            e = ys[0] + su * _COLLAPSE_V_PER_SOC - k_t * (t - _T_REF_C)
        else:
            j = bisect_right(xs, su)
            if j > last:
                j = last
            e = ys[j - 1] + (su - xs[j - 1]) * slopes[j - 1] - k_t * (t - _T_REF_C)
        v = e - k_dip * self._oc * a_o + k_over * self._over * self._over + extra + i * r + v1 + v2 + vp
        if half_m:
            h = self._h
            v -= half_m * (1.0 - h)
            if i > 0.0:
                self._h = 1.0 + (h - 1.0) * exp(-i * h_k)
            elif i < 0.0:
                self._h = -1.0 + (h + 1.0) * exp(i * h_k)
        q = i * (v - eta * e) + eta * i * q_rev
        t_final = self.ambient_c + q * inv_ha
        self.temp_c = t_final + (t - t_final) * a_th
        self.soc = s
        self._v1 = v1
        self._v2 = v2
        self._vp = vp
        self._oc = oc
        self._over = over
        self._surf = x
        self.current = i
        self.cell_voltage = v
        v *= series
        self.voltage = v
        return v

    def current_for_voltage(self, v_pack: float, dt: float) -> float:
        """The current that makes the terminal voltage equal v_pack at the end of a step of dt (algebraic CV solve, see notes §0.2); may be negative."""
        rest, r_ohmic, g_charge, extra, vp, r_pol, vp_max, r_dis, g_dis, x0, b_x = self.cv_terms(dt)
        target = v_pack / self.series
        charge_rhs = target - rest - extra
        s = self.soc + x0
        g = g_charge + g_charge * b_x
        i = self._solve_ocv(s, charge_rhs, r_ohmic + r_pol, g)
        if i > 0.0 and vp + i * r_pol > vp_max:
            # The gassing cap holds: polarisation is a constant, not a resistance, for this step.
            i = self._solve_ocv(s, charge_rhs + vp - vp_max, r_ohmic, g)
        if i > 0.0:
            return i
        i = self._solve_ocv(s, target - rest, r_dis, g_dis + g_dis * b_x)
        # Between the discharge and charge branches (O2 overvoltage step) no current flows.
        return i if i < 0.0 else 0.0

    def cv_terms(self, dt: float) -> tuple:
        """One cell's voltage at the end of a step of dt as a function of its current i: on charge
        U(soc + g_charge*i) + rest + extra + r_ohmic*i + (min(vp + i*r_pol, vp_max) - vp), on discharge
        U(soc + g_dis*i) + rest + r_dis*i (what `step` computes, with everything that does not
        depend on i in `rest`), where the OCV is read at the surface: soc + x0 + g*b_x*i further on."""
        if dt != self._dt:
            self._set_dt(dt)
        (r0, r1b, a1, r2b, a2, ea_r, ea_r_ref, kc, kd, eps, inv_w0, w_t, dv_o2, k_t, q_rev,
         ds_k, a_th, inv_ha, xs, ys, slopes, last, series, a_p, vp_max, k_dip, a_o, k_over, half_m, h_k, a_x,
         b_x) = self._k
        s = self.soc
        t = self.temp_c
        f = exp(ea_r / (t + _KELVIN) - ea_r_ref)
        vp = self._vp * a_p
        rest = (self._v1 * a1 + self._v2 * a2 - k_t * (t - _T_REF_C) + vp - k_dip * self._oc * a_o
                + k_over * self._over * self._over - half_m * (1.0 - self._h))
        r_ohmic = (r0 + r1b + r2b) * f
        eta = 1.0 - exp((s - 1.0) * inv_w0 / max(_W_FLOOR, 1.0 + w_t * (t - _T_REF_C)))
        r_pol = kc / (1.0 - s + eps) * (1.0 - a_p)
        return (rest, r_ohmic, eta * ds_k, (1.0 - eta) * dv_o2, vp, r_pol, vp_max,
                r_ohmic + kd / ((s if s > 0.0 else 0.0) + eps), ds_k, self._surf * a_x, b_x)

    def _solve_ocv(self, s: float, rhs: float, r: float, g: float) -> float:
        """Solve rhs = U(s + g*i) + r*i for i exactly on the piecewise-linear OCV table.

        The left side rises monotonically with i, so walking from the present segment towards
        the solution never turns back."""
        xs, ys, slopes = self._xs, self._ys, self._slopes
        last = len(xs) - 1
        j = min(max(bisect_right(xs, s), 1), last)
        while True:
            slope = slopes[j - 1]
            i = (rhs - ys[j - 1] - (s - xs[j - 1]) * slope) / (r + slope * g)
            s_end = s + g * i
            if s_end > xs[j] and j < last:
                j += 1
            elif s_end < xs[j - 1] and j > 1:
                j -= 1
            elif s_end < 0.0:
                # Past empty the OCV collapses as `step` reads it: a voltage held there (a discharge's end held)
                # draws a current that falls to nothing, not one that runs on at the table's first slope.
                i = (rhs - ys[0] - s * _COLLAPSE_V_PER_SOC) / (r + _COLLAPSE_V_PER_SOC * g)
                if s + g * i < _SOC_FLOOR:
                    i = (rhs - ys[0] - _SOC_FLOOR * _COLLAPSE_V_PER_SOC) / r
                return i
            else:
                return i
