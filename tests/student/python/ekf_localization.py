"""EKF localization (EL2320 lab): a correct solution of the student contract, in Python.

Conventions: vectors are 1-D NumPy arrays, matrices 2-D arrays, the map M is 2 x N
(M[0, j] = x, M[1, j] = y), indices are 0-based, every angle this file computes is
wrapped to [-pi, pi). A function of several outputs returns them as a tuple in the
contract's order (or as a dict of the contract's names, as init does).
"""
import math

import numpy as np


def wrap(angle):
    """An angle wrapped to [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def symmetrise(A):
    return (A + A.T) / 2


def calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu):
    # EL2320 eq. 4, zero at the first step.
    if delta_t == 0:
        return np.zeros(3)
    omega_R = 2 * math.pi * e_R / (E_T * delta_t)
    omega_L = 2 * math.pi * e_L / (E_T * delta_t)
    v = (omega_R * R_R + omega_L * R_L) / 2
    omega = (omega_R * R_R - omega_L * R_L) / B
    return np.array([v * delta_t * math.cos(mu[2]),
                     v * delta_t * math.sin(mu[2]),
                     wrap(omega * delta_t)])


def predict(mu, sigma, u, R):
    # EL2320 Alg. 1: mu_bar = mu + u, Sigma_bar = G Sigma G^T + R.
    mu_bar = mu + u
    mu_bar[2] = wrap(mu_bar[2])
    G = np.array([[1, 0, -u[1]], [0, 1, u[0]], [0, 0, 1]])
    return mu_bar, symmetrise(G @ sigma @ G.T + R)


def observation_model(x, M, j):
    # EL2320 eq. 6: range and bearing of landmark j.
    dx, dy = M[0, j] - x[0], M[1, j] - x[1]
    return np.array([math.hypot(dx, dy), wrap(math.atan2(dy, dx) - x[2])])


def jacobian_observation_model(x, M, j, z_hat):
    dx, dy = M[0, j] - x[0], M[1, j] - x[1]
    r = z_hat[0]
    return np.array([[-dx / r, -dy / r, 0], [dy / r**2, -dx / r**2, -1]])


def associate(mu_bar, sigma_bar, z_i, M, Lambda_M, Q):
    # EL2320 Alg. 2: maximum likelihood over the landmarks, on ln(psi).
    n = M.shape[1]
    nu, S, H = np.zeros((n, 2)), np.zeros((n, 2, 2)), np.zeros((n, 2, 3))
    D, log_psi = np.zeros(n), np.zeros(n)
    for j in range(n):
        z_hat = observation_model(mu_bar, M, j)
        H[j] = jacobian_observation_model(mu_bar, M, j, z_hat)
        S[j] = H[j] @ sigma_bar @ H[j].T + Q
        nu[j] = [z_i[0] - z_hat[0], wrap(z_i[1] - z_hat[1])]
        D[j] = nu[j] @ np.linalg.solve(S[j], nu[j])
        log_psi[j] = -0.5 * math.log(np.linalg.det(2 * math.pi * S[j])) - 0.5 * D[j]
    c = int(np.argmax(log_psi))
    return c, bool(D[c] >= Lambda_M), nu, S, H


def batch_associate(mu_bar, sigma_bar, z, M, Lambda_M, Q):
    c, outlier, nu_bar, H_bar = [], [], [], []
    for i in range(z.shape[1]):
        c_i, out_i, nu, _, H = associate(mu_bar, sigma_bar, z[:, i], M, Lambda_M, Q)
        c.append(c_i)
        outlier.append(out_i)
        nu_bar.extend(nu[c_i])
        H_bar.extend(H[c_i])
    return c, outlier, np.array(nu_bar), np.array(H_bar).reshape(-1, 3)


def update(mu_bar, sigma_bar, H, S, nu):
    # EL2320 Alg. 3.
    K = sigma_bar @ H.T @ np.linalg.inv(S)
    mu = mu_bar + K @ nu
    mu[2] = wrap(mu[2])
    return mu, symmetrise((np.eye(3) - K @ H) @ sigma_bar)


def batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar):
    # EL2320 Alg. 4, second half.
    S = H_bar @ sigma_bar @ H_bar.T + Q_bar
    K = sigma_bar @ H_bar.T @ np.linalg.inv(S)
    mu = mu_bar + K @ nu_bar
    mu[2] = wrap(mu[2])
    return mu, symmetrise((np.eye(3) - K @ H_bar) @ sigma_bar)


def init(dataset):
    deg = math.pi / 180
    R = np.diag([0.01**2, 0.01**2, deg**2])
    Q = np.diag([0.01**2, deg**2])
    delta_M = 0.999
    if dataset == "outliers":
        Q = 0.2**2 * np.eye(2)
    elif dataset == "no-odometry":
        R, Q, delta_M = np.eye(3), 0.1**2 * np.eye(2), 1
    Lambda_M = math.inf if delta_M == 1 else -2 * math.log(1 - delta_M)
    return {"mu": np.zeros(3), "sigma": 1e-10 * np.eye(3), "R": R, "Q": Q,
            "Lambda_M": Lambda_M}
