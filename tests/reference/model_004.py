"""Model 004's equations in plain numpy (smoothed contact), written from the paper's
eq. (9)-(11) and the module docstrings independently of the JAX code: the reference
for the vector-field test and the scipy peer of `benchmarks/limiters.py`.

The matrices (FE shaft, modal basis) are taken from the scene; the forces (unbalance,
internal friction, limiters, energy rate) are re-derived here.
"""

import numpy as np


def _sigmoid(z):
    return 0.5 * (1 + np.tanh(z / 2))


def _softplus(z):
    return np.logaddexp(0.0, z)


class NumpyModel004:
    def __init__(self, scene):
        g = lambda a: np.asarray(a, dtype=float)  # noqa: E731
        self.M, self.K, self.G1 = g(scene.M), g(scene.K), g(scene.G1)
        M, C, G1, K, Ci, J = (g(a) for a in scene.rotor.matrices())
        P = g(scene.basis)
        self.D = P.T @ (C + Ci) @ P                          # external + internal damping
        self.Kc = P.T @ Ci @ J @ P                           # circulatory: N Ci J
        self.Minv = np.linalg.inv(self.M)
        self.disk = P[np.asarray(scene.rotor.disk_dofs)[:2]]
        self.N, self.eps, self.phase = float(scene.N), float(scene.eps), float(scene.phase)
        self.radius = 2 * np.sqrt(float(scene.rotor.beta))
        lim = scene.limiters
        self.angles = g(lim.angles)
        self.chi, self.kappa, self.eta, self.f = (g(a) for a in (lim.clearance, lim.stiffness, lim.damping,
                                                                 lim.friction))
        self.ell = float(lim.smoothing)
        self.n = self.M.shape[0]

    def limiter_force(self, pos, vel):
        F = np.zeros(2)
        for a, chi, kap, eta, f in zip(self.angles, self.chi, self.kappa, self.eta, self.f):
            e, t = np.array([np.cos(a), np.sin(a)]), np.array([-np.sin(a), np.cos(a)])
            d, dd = e @ pos - chi, e @ vel
            r = kap * self.ell * _softplus(d / self.ell) + eta * dd * _sigmoid(d / self.ell)
            R = r * _sigmoid(r / (self.ell * kap))
            V = self.N * self.radius + t @ vel
            F -= R * (e + f * np.tanh(V / 1e-6) * t)
        return F

    def __call__(self, t, y):
        n, N = self.n, self.N
        q, qd = y[:n], y[n:2 * n]
        pos, vel = self.disk @ q, self.disk @ qd
        a = N * t + self.phase
        f_disk = self.eps * N**2 * np.array([np.cos(a), np.sin(a)]) + self.limiter_force(pos, vel)
        f = self.disk.T @ f_disk
        qdd = self.Minv @ (f - (self.D + N * self.G1) @ qd - (self.K + N * self.Kc) @ q)
        power = qd @ f - qd @ self.D @ qd - N * qd @ self.Kc @ q
        return np.concatenate([qd, qdd, [power]])
