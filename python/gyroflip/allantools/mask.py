"""ITU-T limits for TDEV and MTIE (seconds, tau in seconds): the primary reference clock (G.811,
2016 amendment), the primary reference time clock classes A and B (G.8272, 11/2018, Tables 1-4)
and the enhanced PRTC (G.8272.1, 2017 amendment, Tables 1-2); the same limits allantools' mask
module gives. Each is piecewise: constant, or linear in tau, per interval."""


def prc_tdev(tau):
    """G.811 PRC TDEV: 3 ns below 100 s, 0.03 ns/s x tau to 1000 s, 30 ns beyond."""
    return 3e-9 if tau < 100 else (0.03e-9 * tau if tau < 1000 else 30e-9)


def prc_mtie(tau):
    """G.811 PRC MTIE: (0.275e-3 tau + 0.025) us below 1000 s, (1e-5 tau + 0.29) us beyond."""
    return 1e-6 * (0.275e-3 * tau + 0.025) if tau < 1000 else 1e-6 * (1e-5 * tau + 0.29)


def eprtc_tdev(tau):
    """G.8272.1 ePRTC TDEV: 1 ns below 30 ks, 3.33333e-5 ns/s x tau to 300 ks, 10 ns beyond."""
    return 1e-9 if tau < 30e3 else (3.33333e-5 * 1e-9 * tau if tau < 300e3 else 10e-9)


def eprtc_mtie(tau):
    """G.8272.1 ePRTC MTIE: 4 ns to 1 s, (0.11114 tau + 3.89) ns to 100 s,
    (0.0375e-3 tau + 15) ns to 400 ks, 30 ns beyond."""
    if tau <= 1:
        return 4e-9
    if tau <= 100:
        return 1e-9 * (0.11114 * tau + 3.89)
    if tau <= 400000:
        return 1e-9 * (0.0375e-3 * tau + 15)
    return 30e-9


def prtcA_tdev(tau):  # noqa: N802 (allantools' name)
    """G.8272 PRTC-A TDEV: 3 ns below 100 s, 0.03 ns/s x tau to 1000 s, 30 ns beyond."""
    return 3e-9 if tau < 100 else (0.03e-9 * tau if tau < 1000 else 30e-9)


def prtcB_tdev(tau):  # noqa: N802
    """G.8272 PRTC-B TDEV: 1 ns below 100 s, 0.01 ns/s x tau to 500 s, 5 ns beyond."""
    return 1e-9 if tau < 100 else (0.01e-9 * tau if tau < 500 else 5e-9)


def prtcA_mtie(tau):  # noqa: N802
    """G.8272 PRTC-A MTIE: (0.275e-3 tau + 0.025) us below 273 s, 100 ns beyond."""
    return 1e-6 * (0.275e-3 * tau + 0.025) if tau < 273 else 100e-9


def prtcB_mtie(tau):  # noqa: N802
    """G.8272 PRTC-B MTIE: (0.275e-3 tau + 0.025) us below 54.5 s, 40 ns beyond."""
    return 1e-6 * (0.275e-3 * tau + 0.025) if tau < 54.5 else 40e-9
