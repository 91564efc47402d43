"""Kasdin & Walter's discrete power-law noise (Proc. 1992 IEEE FCS, pp. 274-283), allantools'
`Noise` class: white noise of variance qd filtered by the fractional-difference filter of phase
PSD exponent b (0 WPM, -1 FPM, -2 WFM, -3 FFM, -4 RWFM), by FFT convolution."""

import numpy as np


class Noise:
    """Generator of nr points of power-law noise; generateNoise() fills time_series."""

    def __init__(self, nr=2, qd=1, b=0):
        self.nr, self.qd, self.b = nr, qd, b
        self.time_series = np.array([])

    def set_input(self, nr=2, qd=1, b=0):
        self.nr, self.qd, self.b = nr, qd, b

    def generateNoise(self):  # noqa: N802 (allantools' name)
        """time_series = the first nr points of (white * h), h_0 = 1, h_k = h_{k-1}(k - 1 - b/2)/k."""
        n = self.nr
        w = np.zeros(2 * n)
        w[:n] = np.random.normal(0, np.sqrt(self.qd), n)
        h = np.zeros(2 * n)
        k = np.arange(1, n)
        h[0] = 1.0
        h[1:n] = (-self.b / 2.0 + k - 1) / k
        h[:n] = np.multiply.accumulate(h[:n])
        self.time_series = np.fft.irfft(np.fft.rfft(w) * np.fft.rfft(h))[:n]

    def phase_psd_from_qd(self, tau0=1.0):
        """g_b of S_x = g_b f^b (Kasdin & Walter eqn 39)."""
        return self.qd * 2.0 * (2.0 * np.pi) ** self.b * tau0 ** (self.b + 1.0)

    def frequency_psd_from_qd(self, tau0=1.0):
        """h_a of S_y = h_a f^a, a = b + 2 (eqn 39)."""
        a = self.b + 2.0
        return self.qd * 2.0 * (2.0 * np.pi) ** a * tau0 ** (a - 1.0)

    def c_avar(self):
        """AVAR ~ tau^c for b = -4 .. 0."""
        return {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -2.0}.get(self.b)

    def c_mvar(self):
        """MVAR ~ tau^c for b = -4 .. 0."""
        return {-4: 1.0, -3: 0.0, -2: -1.0, -1: -2.0, 0: -3.0}.get(self.b)

    def adev_from_qd(self, tau0=1.0, tau=1.0):
        """ADEV prefactor (Dawkins, McFerran, Luiten 2007; flicker PM with 3 gamma - ln 2 for
        1.038, Vernotte et al. 2016 Table I, as allantools now uses): AVAR = prefactor^2 tau^c."""
        g = self.phase_psd_from_qd(tau0)
        f_h = 0.5 / tau0
        coeff = {0: 3.0 * f_h / (4.0 * np.pi ** 2),
                 -1: (3 * np.euler_gamma - np.log(2) + 3 * np.log(2.0 * np.pi * f_h * tau)) /
                 (4.0 * np.pi ** 2),
                 -2: 0.5, -3: 2 * np.log(2), -4: 2.0 * np.pi ** 2 / 3.0}[self.b]
        return np.sqrt(coeff * g * (2.0 * np.pi) ** 2)

    def mdev_from_qd(self, tau0=1.0, tau=1.0):
        """MDEV prefactor (Dawkins et al. 2007; flicker FM (27/20) ln 2, Benkler et al. 2015
        Table 1, as allantools now uses)."""
        g = self.phase_psd_from_qd(tau0)
        coeff = {0: 3.0 / (8.0 * np.pi ** 2),
                 -1: (24.0 * np.log(2) - 9.0 * np.log(3)) / 8.0 / np.pi ** 2,
                 -2: 0.25, -3: 27.0 / 20.0 * np.log(2),
                 -4: 11.0 / 20.0 * np.pi ** 2}[self.b]
        return np.sqrt(coeff * g * (2.0 * np.pi) ** 2)

    def pdev_from_qd(self, tau0=1.0, tau=1.0):
        """PDEV prefactor (Vernotte, Lenczner, Bourgeois & Rubiola 2016, Table I): PVAR =
        prefactor^2 tau^c, c as c_mvar."""
        g = self.phase_psd_from_qd(tau0)
        coeff = {0: 3.0 / (2.0 * np.pi ** 2), -1: (3.0 * np.log(16.0) - 1.0) / (2.0 * np.pi ** 2),
                 -2: 3.0 / 5.0, -3: 2.0 * (7.0 - np.log(16.0)) / 5.0,
                 -4: 26.0 / 35.0 * np.pi ** 2}[self.b]
        return np.sqrt(coeff * g * (2.0 * np.pi) ** 2)

    def adev(self, tau0, tau):
        """Predicted ADEV at tau."""
        return np.sqrt(self.adev_from_qd(tau0=tau0, tau=tau) ** 2 * tau ** self.c_avar())

    def mdev(self, tau0, tau):
        """Predicted MDEV at tau."""
        return np.sqrt(self.mdev_from_qd(tau0=tau0, tau=tau) ** 2 * tau ** self.c_mvar())
