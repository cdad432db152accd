"""The results of chatter's commands in Python: dicts (the keys are the CLI's
JSON keys and CSV columns, the tables NumPy arrays) that draw themselves.

``result.plot(ax=None)`` draws with Matplotlib (Debian: python3-matplotlib)
in the colours of the CLI's gnuplot plots and returns the Axes; a notebook
shows the figure as the result's rich display (``_repr_png_``). Matplotlib is
imported only when a figure is drawn: without it, everything but the figures
works and ``plot()`` raises ImportError saying how to install it.
"""
import io


class _Numpy:
    """NumPy, imported at its first use (a figure, an array): `import chatter`
    stays cheap for a post-processor that only reads verdicts (docs/python.md,
    "Python in a loop")."""

    def __getattr__(self, name):
        import numpy
        return getattr(numpy, name)


np = _Numpy()

# The CLI's plot colours (src/plots/plot_kit.hpp).
STABLE = "#8cc97e"    # stable region (drawn 40 % opaque)
CHATTER = "#f08a7e"   # chatter region (30 % opaque)
ENVELOPE = "#1a4d80"  # the stability limit
FLIP = "#7b1fa2"      # limits and boundaries set by a flip (period-doubling) multiplier
FOLD = "#00796b"
TOOL = "#1f77b4"
WORKPIECE = "#e07b00"
RELATIVE = "#202020"
SAMPLE = "#c0392b"    # once-per-period samples, the chatter line
GRID = "#c8c8c8"
# The stability map's colours: blues below rho = 1, oranges to red above.
MAP_COLOURS = [(0.0, "#0b3a6e"), (0.25, "#3f7fbf"), (0.5, "#bcd7ee"), (0.5, "#fdc793"), (0.75, "#ee7640"),
               (1.0, "#7a0c0c")]


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("chatter's plots need Matplotlib (Debian: apt install python3-matplotlib; "
                          "or pip install matplotlib)") from e
    return plt


def _axes(ax, panels=1, figsize=(9, 5), sharex=False):
    """`ax` as a list of `panels` Axes: a new figure when None; a single Axes
    given for a multi-panel plot draws only the first panel."""
    if ax is None:
        plt = _pyplot()
        _, axes = plt.subplots(panels, 1, figsize=figsize, sharex=sharex, squeeze=False, layout="constrained")
        return list(axes[:, 0])
    if isinstance(ax, (list, tuple, np.ndarray)):
        return list(np.ravel(ax))
    return [ax]


def _style(ax, xlabel, ylabel):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, color=GRID, lw=0.6)


class Result(dict):
    """A command's record (a dict) that draws itself; ``info`` holds what the
    dict's keys do not (for tables whose keys are the CSV's columns)."""

    _panels = 1
    _figsize = (9, 5)
    _sharex = False  # the panels share their x axis

    def __init__(self, data=(), info=None):
        super().__init__(data)
        self.info = dict(info or {})

    def plot(self, ax=None):
        raise NotImplementedError

    def _title(self):
        name = self.info.get("name", self.get("name", ""))
        method = self.info.get("method", self.get("method", ""))
        return f"{name} ({method})" if name and method else name or method

    def _repr_png_(self):
        """The figure as PNG bytes for a notebook's rich display (None
        without Matplotlib: the notebook shows the text)."""
        try:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure
        except ImportError:
            return None
        fig = Figure(figsize=self._figsize, dpi=96, layout="constrained")
        FigureCanvasAgg(fig)
        axes = fig.subplots(self._panels, 1, sharex=self._sharex, squeeze=False)[:, 0]
        self.plot(ax=list(axes) if self._panels > 1 else axes[0])
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        return buf.getvalue()

    def __repr__(self):
        keys = ", ".join(self.keys())
        return f"<chatter.{type(self).__name__} {self._title()!s}: {keys}>"

    def _repr_pretty_(self, p, cycle):  # IPython's text: the short form, not every array
        p.text(repr(self))


# ---------------------------------------------------------------- lobes

def _draw_lobes(ax, rpm, depth, top, flip=None, label="stability limit"):
    """The CLI's lobe diagram: stable region filled below the limit, chatter
    above, the limit as a thick line (a gap where none below the searched
    depth), flip-limited stretches drawn over it."""
    finite = np.isfinite(depth)
    shown = np.where(finite, np.minimum(depth, top), top)
    ax.fill_between(rpm, 0, shown, color=STABLE, alpha=0.4, lw=0, label="stable")
    ax.fill_between(rpm, shown, top, color=CHATTER, alpha=0.3, lw=0, label="chatter")
    ax.plot(rpm, np.where(finite, depth, np.nan), color=ENVELOPE, lw=2.2, label=label)
    if flip is not None and np.any(flip & finite):
        ax.plot(rpm, np.where(flip & finite, depth, np.nan), color=FLIP, lw=3.2,
                label="flip (period doubling)")


def _depth_top(depth, depth_max_mm):
    """The depth axis: 1.1 x the deepest finite limit (so every pocket shows),
    at most the searched depth."""
    finite = depth[np.isfinite(depth)]
    top = 1.1 * finite.max() if finite.size else depth_max_mm or 1.0
    return min(top, depth_max_mm) if depth_max_mm else top


class Lobes(Result):
    """chatter.lobes(): the lobe table; ``info``: method, name, warnings,
    notes, depth_max_mm. plot() draws the diagram, sdm's flip-limited speeds
    marked."""

    def plot(self, ax=None):
        ax = _axes(ax, figsize=self._figsize)[0]
        rpm, depth = self["spindle_rpm"], self["depth_limit_mm"]
        top = _depth_top(depth, self.info.get("depth_max_mm"))
        flip = np.asarray(self["multiplier_type"]) == "flip" if "multiplier_type" in self else None
        _draw_lobes(ax, rpm, depth, top, flip)
        ax.set_xlim(rpm.min(), rpm.max())
        ax.set_ylim(0, top)
        _style(ax, "spindle speed (rev/min)", "depth of cut (mm)")
        ax.set_title(self._title())
        ax.legend(loc="upper left", fontsize="small", ncol=4)
        return ax


class UncertainLobes(Result):
    """chatter.uncertain_lobes(): plot() draws the probability of stability
    over speed and depth with the quantile lobes and the nominal one."""

    def plot(self, ax=None):
        ax = _axes(ax, figsize=self._figsize)[0]
        rpm, depths = self["spindle_rpm"], self["depth_mm"]
        from matplotlib.colors import LinearSegmentedColormap
        cmap = LinearSegmentedColormap.from_list(
            "chatter_probability", [(0, "#b2182b"), (0.5, "#fddbc7"), (0.5, "#d1e5f0"), (1, "#2166ac")])
        mesh = ax.pcolormesh(rpm, depths, np.asarray(self["probability_stable"]).T, cmap=cmap, vmin=0, vmax=1,
                             shading="nearest")
        ax.figure.colorbar(mesh, ax=ax, label="probability of stability")
        top = depths[-1]
        for key, colour, dash in (("depth_limit_p05_mm", "#6a00a8", "--"), ("depth_limit_p50_mm", "#e6a800", "-"),
                                  ("depth_limit_p95_mm", "#00796b", "--")):
            if key in self:
                level = int(key.split("_p")[1][:2])
                ax.plot(rpm, np.minimum(self[key], top), dash, color=colour, lw=1.6,
                        label=f"{100 - level} % of samples stable below")
        ax.plot(rpm, np.minimum(self["depth_limit_mm"], top), color="black", lw=2, label="nominal lobe")
        ax.set_ylim(0, top)
        _style(ax, "spindle speed (rev/min)", "depth of cut (mm)")
        ax.set_title(f"{self._title()}, {self.get('samples', '?')} samples")
        ax.legend(loc="upper left", fontsize="small")
        return ax


class Surface(Result):
    """chatter.surface(): plot() draws the depth limit over (speed,
    position) as colours with contours and the best speed at each position."""

    def plot(self, ax=None):
        ax = _axes(ax, figsize=self._figsize)[0]
        positions = np.unique(self["position_mm"])
        rpm = self["spindle_rpm"][: self["spindle_rpm"].size // positions.size]
        depth = np.asarray(self["depth_limit_mm"]).reshape(positions.size, rpm.size)
        finite = depth[np.isfinite(depth)]
        depth_max = self.info.get("depth_max_mm") or (finite.max() if finite.size else 1.0)
        top = min(depth_max, 1.1 * finite.max()) if finite.size else depth_max
        shown = np.where(np.isfinite(depth), np.minimum(depth, top), top)
        from matplotlib.colors import LinearSegmentedColormap
        cmap = LinearSegmentedColormap.from_list(
            "chatter_surface", [(0, "#7a0c0c"), (0.15, "#d7301f"), (0.35, "#fc8d59"), (0.55, "#fee090"),
                                (0.75, "#91bfdb"), (1, "#2c5aa0")])
        mesh = ax.pcolormesh(rpm, positions, shown, cmap=cmap, vmin=0, vmax=top, shading="nearest")
        ax.figure.colorbar(mesh, ax=ax, label="depth limit (mm)")
        if positions.size > 1 and rpm.size > 1:
            cs = ax.contour(rpm, positions, shown, colors=RELATIVE, linewidths=1.0)
            ax.clabel(cs, fontsize="small", fmt="%g")
        best = np.argmax(np.where(np.isfinite(depth), depth, np.inf), axis=1)
        ax.plot(rpm[best], positions, "o-", color="white", mec=RELATIVE, lw=2, label="best speed at each position")
        _style(ax, "spindle speed (rev/min)", "tool position (mm)")
        ax.set_title(f"{self._title()}: lobe surface")
        ax.legend(loc="upper right", fontsize="small")
        return ax


class StabilityMap(Result):
    """chatter.map(): plot() draws the spectral radius over speed and depth
    (log colour scale centred on 1), the boundary rho = 1, and (with
    multiplier_types=True) the unstable points where flip dominates. With
    axes="radial-axial" the x axis is the radial depth a_e (mm; a_e/D without
    a tool diameter) at the map's one speed, and the depth limit searched at
    each immersion is drawn as points."""

    def plot(self, ax=None):
        ax = _axes(ax, figsize=self._figsize)[0]
        from matplotlib.colors import LinearSegmentedColormap, LogNorm
        radial = self.get("axes") == "radial-axial"
        if radial:
            mm = "radial_depth_mm" in self
            rpm = self["radial_depth_mm"] if mm else self["radial_immersion"]
        else:
            rpm = self["spindle_rpm"]
        depth, rho = self["depth_mm"], np.asarray(self["spectral_radius"])
        logs = np.abs(np.log(rho[np.isfinite(rho) & (rho > 0)]))
        spread = np.quantile(logs, 0.9) if logs.size else 1.0
        clip = next((r for r in (1.5, 2, 3, 5, 10) if np.log(r) >= spread), 10)  # the CLI's rule
        cmap = LinearSegmentedColormap.from_list("chatter_map", MAP_COLOURS)
        mesh = ax.pcolormesh(rpm, depth, np.clip(rho, 1 / clip, clip).T, cmap=cmap,
                             norm=LogNorm(vmin=1 / clip, vmax=clip), shading="nearest")
        ax.figure.colorbar(mesh, ax=ax, label="spectral radius ρ")
        if rpm.size > 1 and depth.size > 1:
            ax.contour(rpm, depth, rho.T, levels=[1.0], colors=RELATIVE, linewidths=1.6)
        ax.plot([], [], color=RELATIVE, lw=1.6, label="ρ = 1")
        if "multiplier_type" in self:
            types = np.asarray(self["multiplier_type"])
            i, k = np.nonzero(types == "flip")
            if i.size:
                ax.plot(rpm[i], depth[k], "x", color=FLIP, ms=4, label="flip dominates (μ ≈ −1)")
        ax.set_xlim(rpm.min(), rpm.max())
        ax.set_ylim(depth.min(), depth.max())
        if radial:
            limit = np.asarray(self["depth_limit_mm"], dtype=float)
            shown = np.isfinite(limit) & (limit <= depth.max())
            ax.plot(rpm[shown], limit[shown], "o", color="black", mec="white", ms=4,
                    label="depth limit searched at each a_e")
            _style(ax, "radial depth of cut a_e (mm)" if mm else "radial immersion a_e/D (-)",
                   "axial depth of cut a_p (mm)")
            ax.set_title(f"{self.get('name', '')}: spectral radius (sdm) at {self['spindle_rpm']:g} rev/min")
        else:
            _style(ax, "spindle speed (rev/min)", "depth of cut (mm)")
            ax.set_title(f"{self.get('name', '')}: spectral radius (sdm)")
        ax.legend(loc="upper left", fontsize="small")
        return ax


class Comparison(Result):
    """chatter.compare(): plot() draws every method's limit, each in the
    CLI's style, sdm's flip-limited speeds marked."""

    def plot(self, ax=None):
        ax = _axes(ax, figsize=self._figsize)[0]
        from . import _chatter
        styles = _chatter._plot_styles()
        rpm = self["spindle_rpm"]
        tops = []
        order = sorted(self["methods"], key=lambda m: -styles.get(m, ("", 1.0, [], 0))[1])  # widest first
        for m in order:
            colour, width, dash, point = styles.get(m, ("#000000", 1.0, [], 0))
            depth = self[f"depth_limit_mm_{m}"]
            finite = np.isfinite(depth)
            tops.extend(depth[finite])
            y = np.where(finite, depth, np.nan)
            if point:
                every = max(1, rpm.size // 100)
                ax.plot(rpm[::every], y[::every], "o", mfc="none", color=colour, ms=5, label=m)
            else:
                ax.plot(rpm, y, color=colour, lw=0.6 * width, dashes=dash or (None, None), label=m)
            types = self.get(f"multiplier_type_{m}")
            if types is not None and np.any(np.asarray(types) == "flip"):
                ax.plot(rpm, np.where(np.asarray(types) == "flip", depth, np.nan), ".-", color=FLIP, lw=2.5,
                        ms=4, label=f"{m}: flip (period doubling)")
        top = min(1.1 * max(tops), self.get("depth_max_mm", np.inf)) if tops else self.get("depth_max_mm", 1.0)
        ax.set_xlim(rpm.min(), rpm.max())
        ax.set_ylim(0, top)
        _style(ax, "spindle speed (rev/min)", "depth limit (mm)")
        ax.set_title(f"{self.get('name', '')}: depth limit by method")
        ax.legend(loc="upper left", fontsize="small")
        return ax


# ---------------------------------------------------------------- simulation

class Simulation(Result):
    """chatter.simulate(): plot() draws the relative displacement with its
    once-per-period samples, the cutting force and the spectrum (three
    panels; ``ax`` a sequence of three Axes, or one Axes for the first)."""

    _panels = 3
    _figsize = (9, 8)

    def plot(self, ax=None):
        axes = _axes(ax, panels=3, figsize=self._figsize)
        s, p = self["series"], self["periodic"]
        if len(s["time_s"]) == 0:
            raise ValueError("no time series to draw (simulate with record_series=True)")
        t = s["time_s"] * 1e3
        a = axes[0]
        a.plot(t, s["rel_x_um"], color=TOOL, lw=0.8, label="x (feed direction)")
        if np.max(np.abs(s["rel_y_um"])) > 1e-3 * np.max(np.abs(s["rel_x_um"])):
            a.plot(t, s["rel_y_um"], color=WORKPIECE, lw=0.8, label="y")
        a.plot(p["time_s"] * 1e3, p["rel_x_um"], ".", color=SAMPLE, ms=3, label="x once per period")
        _style(a, "time (ms)", "relative displacement (µm)")
        a.legend(loc="upper left", fontsize="small", ncol=3)
        head = f"{self.get('config', '')}, {self['spindle_rpm']:g} rev/min, {self['depth_mm']:g} mm: {self['verdict']}"
        if self.get("chatter_frequency_hz") is not None:
            head += f" at {self['chatter_frequency_hz']:.4g} Hz"
        if self.get("growth_per_period") is not None:
            head += f", |μ| = {self['growth_per_period']:.4g}"
        a.set_title(head)
        a.set_xlim(t[0], t[-1])
        if len(axes) > 1:
            a = axes[1]
            a.set_xlim(t[0], t[-1])
            a.plot(t, s["force_x_n"], color=TOOL, lw=0.8, label="F_x")
            if np.max(np.abs(s["force_y_n"])) > 1e-3 * np.max(np.abs(s["force_x_n"])):
                a.plot(t, s["force_y_n"], color=WORKPIECE, lw=0.8, label="F_y")
            _style(a, "time (ms)", "force on the tool (N)")
            a.legend(loc="upper left", fontsize="small", ncol=2)
        if len(axes) > 2:
            a = axes[2]
            sp = self["spectrum"]
            f, amp, harm = sp["frequency_hz"], sp["amplitude_um"], sp["harmonic"]
            if f.size:
                floor = max(amp[1:].max() * 1e-7, 1e-300) if amp.size > 1 else 1e-12
                a.semilogy(f, np.maximum(amp, floor), color=RELATIVE, lw=0.8, label="relative displacement")
                h = harm > 0
                a.semilogy(f[h], np.maximum(amp[h], floor), "o", mfc="none", color=TOOL, label="forced harmonics")
                if self.get("dominant_frequency_hz") is not None:
                    a.axvline(self["dominant_frequency_hz"], color=SAMPLE, lw=1.2,
                              label=("chatter " if self["verdict"] == "chatter" else "least damped ")
                              + f"{self['dominant_frequency_hz']:.4g} Hz")
            _style(a, "frequency (Hz)", "amplitude (µm)")
            a.legend(loc="upper right", fontsize="small")
        return axes if len(axes) > 1 else axes[0]


# ---------------------------------------------------------------- receptance

def _phase_deg(g):
    """Phase in degrees, wrapped to (-270, 90] (a receptance does not jump at -180)."""
    p = np.degrees(np.angle(g))
    return np.where(p > 90.0, p - 360.0, p)


class Frf(Result):
    """chatter.frf(): the receptance table (m/N); receptance(body, term) as a
    complex array; plot() draws magnitude and phase of the xx (and yy) terms
    of tool, workpiece and their relative motion (two panels)."""

    _panels = 2
    _figsize = (9, 7)
    _sharex = True

    def receptance(self, body="relative", term="xx"):
        """The complex receptance, m/N: body tool, workpiece or relative; term xx, xy or yy."""
        return self[f"{body}_{term}_real_m_per_n"] + 1j * self[f"{body}_{term}_imag_m_per_n"]

    def plot(self, ax=None):
        axes = _axes(ax, panels=2, figsize=self._figsize, sharex=True)
        f = self["frequency_hz"]
        for term, dash in (("xx", "-"), ("yy", "--")):
            for body, colour in (("tool", TOOL), ("workpiece", WORKPIECE), ("relative", RELATIVE)):
                g = self.receptance(body, term)
                if not np.any(np.abs(g) > 0):
                    continue  # rigid along this term
                axes[0].semilogy(f, np.abs(g), dash, color=colour, lw=1.4 if body == "relative" else 1.0,
                                 label=f"{body} {term}")
                if len(axes) > 1:
                    axes[1].plot(f, _phase_deg(g), dash, color=colour, lw=1.4 if body == "relative" else 1.0)
        _style(axes[0], "frequency (Hz)", "magnitude |G| (m/N)")
        axes[0].set_title(f"{self.get('name', '')}: receptance")
        axes[0].legend(loc="upper right", fontsize="small", ncol=2)
        if len(axes) > 1:
            _style(axes[1], "frequency (Hz)", "phase (deg)")
            axes[1].set_yticks(np.arange(-270, 91, 45))
        return axes if len(axes) > 1 else axes[0]


class ModalFit(Result):
    """chatter.fit(): the fitted modes per record and the [[<body>.modes]]
    fragment; plot() draws measured against fitted magnitude and phase."""

    _panels = 2
    _figsize = (9, 7)
    _sharex = True

    def plot(self, ax=None):
        axes = _axes(ax, panels=2, figsize=self._figsize, sharex=True)
        colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]
        for r, rec in enumerate(self["records"]):
            c = colours[r % len(colours)]
            who = (rec.get("record", "") + " ") if len(self["records"]) > 1 else ""
            fm, gm = rec["measured_frequency_hz"], rec["measured_receptance_m_per_n"]
            lo, hi = rec["band_min_hz"], rec["band_max_hz"]
            pad = 0.03 * (hi - lo)
            keep = (fm >= lo - pad) & (fm <= hi + pad)
            ff, gf = rec["fitted_frequency_hz"], rec["fitted_receptance_m_per_n"]
            axes[0].semilogy(fm[keep], np.abs(gm[keep]), ".", color=c, alpha=0.45, ms=3, label=who + "measured")
            axes[0].semilogy(ff, np.abs(gf), color=c, lw=2,
                             label=f"{who}fit, {len(rec['modes'])} mode(s), error {100 * rec['fit_error']:.3g} %")
            if len(axes) > 1:
                axes[1].plot(fm[keep], _phase_deg(gm[keep]), ".", color=c, alpha=0.45, ms=3)
                axes[1].plot(ff, _phase_deg(gf), color=c, lw=2)
        _style(axes[0], "frequency (Hz)", "magnitude |G| (m/N)")
        axes[0].set_title(f"Modal fit: {self.get('file', '')}")
        axes[0].legend(loc="upper right", fontsize="small")
        if len(axes) > 1:
            _style(axes[1], "frequency (Hz)", "phase (deg)")
        return axes if len(axes) > 1 else axes[0]


class Detection(Result):
    """chatter.detect(): plot() draws the recording's spectrum, the forced
    lines (tooth passing, spindle) and the chatter line."""

    def plot(self, ax=None):
        ax = _axes(ax, figsize=self._figsize)[0]
        sp = self["spectrum"]
        f, amp = sp["frequency_hz"], sp["amplitude"]
        ax.semilogy(f, np.maximum(amp, amp.max() * 1e-9 if amp.size else 1e-300), color=RELATIVE, lw=0.7,
                    label="spectrum")
        for kind, colour, marker in (("tooth-passing", TOOL, "o"), ("spindle", WORKPIECE, "s"),
                                     ("chatter", SAMPLE, "v")):
            peaks = [p for p in self["peaks"] if p["kind"] == kind]
            if peaks:
                ax.semilogy([p["frequency_hz"] for p in peaks], [p["amplitude"] for p in peaks], marker,
                            mfc="none", color=colour, label=kind)
        if self.get("chatter_frequency_hz") is not None:
            ax.axvline(self["chatter_frequency_hz"], color=SAMPLE, lw=1.2)
        _style(ax, "frequency (Hz)", "amplitude")
        verdict = f"CHATTER at {self['chatter_frequency_hz']:.5g} Hz" if self["chatter"] else "no chatter"
        ax.set_title(f"{self.get('recording', '')}: {verdict}")
        ax.legend(loc="upper right", fontsize="small")
        return ax
