"""allantools' `Plot`: a log-log figure of a Dataset's results. matplotlib is imported when a Plot
is made, never by `import gyroflip.allantools` (it is not a dependency of gyroflip)."""


class Plot:
    """Plot(no_display=False), as allantools: plot(dataset, errorbars=False, grid=False,
    **kwargs), show(), save(filename). Without matplotlib: RuntimeError, as allantools. `ax`
    (keyword only) draws into an existing matplotlib axes (gyroflip's addition)."""

    def __init__(self, no_display=False, *, ax=None):
        try:
            import matplotlib  # pylint: disable=import-outside-toplevel
            if no_display:
                matplotlib.use("Agg")
            import matplotlib.pyplot as plt  # pylint: disable=import-outside-toplevel
        except ImportError:
            raise RuntimeError("Matplotlib is required for plotting") from None
        self.plt = plt
        if ax is None:
            self.fig, self.ax = plt.subplots()
        else:
            self.fig, self.ax = ax.figure, ax
        self.ax.set_xscale("log")
        self.ax.set_yscale("log")

    def plot(self, atDataset, errorbars=False, grid=False, **kwargs):  # noqa: N803
        out = atDataset.out
        if errorbars:
            self.ax.errorbar(out["taus"], out["stat"], yerr=out["stat_err"], **kwargs)
        else:
            self.ax.plot(out["taus"], out["stat"], **kwargs)
        self.ax.set_xlabel("Tau")
        self.ax.set_ylabel(out["stat_id"])
        if grid:
            self.ax.grid(True, which="minor", ls="-", color="0.65")
            self.ax.grid(True, which="major", ls="-", color="0.25")
        else:
            self.ax.grid(False)

    def show(self):
        self.plt.show()

    def save(self, f):
        self.fig.savefig(f)
