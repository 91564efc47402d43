"""Streaming deviations (allantools' realtime module; Dobrogowski & Kasznia, Proc. 2007 IEEE FCS):
OADEV, OHDEV and TDEV/MDEV updated point by point at fixed averaging factors, or with factors
added as the stream grows (auto_afs: pts_per_decade per decade)."""

import numpy as np


class dev_realtime:  # noqa: N801 (allantools' names)
    """Base: the phase so far, the factors and their deviations."""

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006
        self.x = []
        self.afs = np.array([1]) if auto_afs else afs  # kept as passed, as allantools
        self.auto_afs = auto_afs
        self.af_taus = np.logspace(0, 1, pts_per_decade + 1)[:-1]
        self.af_idx = 0
        self.af_decade = 0
        self.dev = np.zeros(len(self.afs))
        self.tau0 = tau0

    def update_af(self):
        """auto_afs: add the next factor of the log grid once 2 af + 1 points exist."""
        idx, decade = self.af_idx + 1, self.af_decade
        if idx == len(self.af_taus):
            idx, decade = 0, decade + 1
        af = int(np.round(10.0 ** decade * self.af_taus[idx]))
        if len(self.x) >= 2 * af + 1:
            self.afs = np.append(self.afs, af)
            self.add_af()
            self.dev = np.append(self.dev, 0)
            self.af_idx, self.af_decade = idx, decade

    def add_phase(self, xnew):
        """A phase sample: every factor's terms ending at it, then (auto_afs) the next factor."""
        self.x.append(xnew)
        for k, af in enumerate(self.afs):
            self._add_terms(k, af)
        if self.auto_afs:
            self.update_af()

    def _add_terms(self, idx, af):
        pass

    def add_frequency(self, f):
        """A fractional-frequency sample: the phase integrates it (starting at 0)."""
        if not self.x:
            self.add_phase(0)
        self.add_phase(self.x[-1] + f)

    def taus(self):
        return self.tau0 * np.asarray(self.afs)

    def add_af(self):
        pass

    def devs(self):
        return self.dev


class _summed(dev_realtime):
    """A deviation from one sum of squared differences per factor (S)."""

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006
        super().__init__(afs=afs, tau0=tau0, auto_afs=auto_afs, pts_per_decade=pts_per_decade)
        self.S = np.zeros(len(self.afs))

    def add_af(self):
        self.S = np.append(self.S, 0)

    def _describe(self, name):
        return f"n_pts: {len(self.x)} " + "".join(
            f"{name}({af})={d:f} " for af, d in zip(self.afs, self.dev))


class oadev_realtime(_summed):  # noqa: N801
    """OADEV: each new point adds the term ending at it to the sum of squares."""

    def _add_terms(self, idx, af):
        if len(self.x) >= 2 * af + 1:
            self.update_S(idx)

    def update_S(self, idx):  # noqa: N802
        af = int(self.afs[idx])
        i = len(self.x) - 1
        self.S[idx] += (self.x[i] - 2 * self.x[i - af] + self.x[i - 2 * af]) ** 2
        self.dev[idx] = np.sqrt(self.S[idx] / (2 * (af * self.tau0) ** 2 * (i + 1 - 2 * af)))

    def __str__(self):
        return self._describe("ADEV")


class ohdev_realtime(_summed):  # noqa: N801
    """OHDEV: the third-difference term ending at each new point."""

    def _add_terms(self, idx, af):
        if len(self.x) > 3 * af:
            self.update_S(idx)

    def update_S(self, idx):  # noqa: N802
        af = int(self.afs[idx])
        i = len(self.x) - 1
        x = self.x
        self.S[idx] += (x[i] - 3 * x[i - af] + 3 * x[i - 2 * af] - x[i - 3 * af]) ** 2
        self.dev[idx] = np.sqrt(self.S[idx] / (6.0 * (af * self.tau0) ** 2 * (i + 1.0 - 3 * af)))

    def __str__(self):
        return self._describe("OHDEV")


class tdev_realtime(_summed):  # noqa: N801
    """TDEV (and MDEV by mdev()): the MDEV inner sum slides by one third difference per point."""

    def __init__(self, afs=[1], tau0=1.0, auto_afs=False, pts_per_decade=4):  # noqa: B006
        super().__init__(afs=afs, tau0=tau0, auto_afs=auto_afs, pts_per_decade=pts_per_decade)
        self.So = np.zeros(len(self.afs))

    def add_af(self):
        super().add_af()
        self.So = np.append(self.So, 0)

    def _add_terms(self, idx, af):
        if len(self.x) >= 3 * af + 1:
            self.update_S(idx)
        elif len(self.x) >= 2 * af + 1:
            self.update_S3n(idx)

    def update_S3n(self, idx):  # noqa: N802
        af = int(self.afs[idx])
        j = len(self.x) - 1
        self.S[idx] += self.x[j] - 2 * self.x[j - af] + self.x[j - 2 * af]
        if len(self.x) == 3 * af:
            self.So[idx] = self.S[idx] ** 2
            self.update_dev(idx)

    def update_dev(self, idx):
        af = int(self.afs[idx])
        n = len(self.x)
        self.dev[idx] = np.sqrt(self.So[idx] / (6.0 * (n - 3 * af + 1.0) * af ** 2))

    def update_S(self, idx):  # noqa: N802
        af = int(self.afs[idx])
        i = len(self.x) - 1
        x = self.x
        self.S[idx] += x[i] - 3 * x[i - af] + 3 * x[i - 2 * af] - x[i - 3 * af]
        self.So[idx] += self.S[idx] ** 2
        self.update_dev(idx)

    def mdev(self):
        return np.array([d * np.sqrt(3) / (af * self.tau0) for af, d in zip(self.afs, self.dev)])

    def __str__(self):
        return self._describe("TDEV")
