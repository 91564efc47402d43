#!/usr/bin/env python3
"""Reference values of the random-effects pooling (method::fit_delta_n_random_effects) on the BCG
trials (tests/vectors/metafor-bcg/PROVENANCE.md): an independent NumPy transcription of
DerSimonian & Laird's moment estimator in its meta-regression form and of Knapp & Hartung's
covariance. Prints what tests/method/test_pooling.cpp checks. Usage: python3 random_effects_bcg.py
(Debian's python3-numpy)."""
import numpy as np

# metafor::dat.bcg: tpos, tneg, cpos, cneg, ablat (Colditz et al. 1994).
BCG = [(4, 119, 11, 128, 44), (6, 300, 29, 274, 55), (3, 228, 11, 209, 42),
       (62, 13536, 248, 12619, 52), (33, 5036, 47, 5761, 13), (180, 1361, 372, 1079, 44),
       (8, 2537, 10, 619, 19), (505, 87886, 499, 87892, 13), (29, 7470, 45, 7232, 27),
       (17, 1699, 65, 1600, 42), (186, 50448, 141, 27197, 18), (5, 2493, 3, 2338, 33),
       (27, 16886, 29, 17825, 33)]


def random_effects(y, v, X):
    """tau^2 (DL), coefficients and Knapp-Hartung covariance of y ~ X b + u + e."""
    k, p = X.shape
    W = np.diag(1 / v)
    A = np.linalg.inv(X.T @ W @ X)
    P = W - W @ X @ A @ X.T @ W
    tau2 = max(0.0, (y @ P @ y - (k - p)) / np.trace(P))
    Ws = np.diag(1 / (v + tau2))
    As = np.linalg.inv(X.T @ Ws @ X)
    b = As @ X.T @ Ws @ y
    r = y - X @ b
    return tau2, b, As * (r @ Ws @ r) / (k - p)


def main():
    a, b, c, d, lat = (np.array(col, float) for col in zip(*BCG))
    y = np.log((a / (a + b)) / (c / (c + d)))
    v = 1 / a - 1 / (a + b) + 1 / c - 1 / (c + d)
    tau2, coef, cov = random_effects(y, v, np.ones((len(y), 1)))
    print(f"intercept only: tau2 {tau2!r} mean {coef[0]!r} KH se {np.sqrt(cov[0, 0])!r}")
    x = lat - lat.mean()
    tau2, coef, cov = random_effects(y, v, np.column_stack([np.ones_like(x), x]))
    print(f"on latitude (centred on {lat.mean()!r}): tau2 {tau2!r} coef {coef.tolist()!r} "
          f"KH cov {cov.tolist()!r}")


if __name__ == "__main__":
    main()
