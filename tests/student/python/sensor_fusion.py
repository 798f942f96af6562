"""Fusing odometry with an indoor positioning sensor: a correct solution of the student
contract, in Python. A pose is [x, y, theta], a platform's reading [x, y, I]."""
import math

import numpy as np


def wrap(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


def innovation(mu, z):
    nu = z - mu
    nu[2] = wrap(nu[2])
    return nu


def combine_platforms(p1, p2):
    w1, w2 = p1[2] / (p1[2] + p2[2]), p2[2] / (p1[2] + p2[2])
    return np.array([w1 * p1[0] + w2 * p2[0], w1 * p1[1] + w2 * p2[1],
                     math.atan2(p1[1] - p2[1], p1[0] - p2[0])])


def heading_sigma(p1, p2, c_xy):
    s1, s2 = c_xy / p1[2], c_xy / p2[2]
    return math.sqrt(s1**2 + s2**2) / math.hypot(p1[0] - p2[0], p1[1] - p2[1])


def measurement_noise(p1, p2, c_xy):
    sxy = max(c_xy / p1[2], c_xy / p2[2])
    return np.diag([sxy**2, sxy**2, heading_sigma(p1, p2, c_xy) ** 2])


def in_field_of_view(z, radius):
    return bool(math.hypot(z[0], z[1]) <= radius)


def predict(mu, sigma, odom_prev, odom, k_xy, k_theta):
    # The odometry's increment in the frame of its previous pose, applied along the
    # belief's own heading.
    c0, s0 = math.cos(odom_prev[2]), math.sin(odom_prev[2])
    gx, gy = odom[0] - odom_prev[0], odom[1] - odom_prev[1]
    dx, dy = c0 * gx + s0 * gy, -s0 * gx + c0 * gy
    dtheta = wrap(odom[2] - odom_prev[2])
    c, s = math.cos(mu[2]), math.sin(mu[2])
    mu_bar = np.array([mu[0] + c * dx - s * dy, mu[1] + s * dx + c * dy,
                       wrap(mu[2] + dtheta)])
    G = np.array([[1, 0, -s * dx - c * dy], [0, 1, c * dx - s * dy], [0, 0, 1]])
    moved = math.hypot(dx, dy)
    R = np.diag([(k_xy * moved) ** 2, (k_xy * moved) ** 2,
                 (k_theta * (moved + abs(dtheta))) ** 2])
    A = G @ sigma @ G.T + R
    return mu_bar, (A + A.T) / 2


def mahalanobis(mu_bar, sigma_bar, z, Q):
    nu = innovation(mu_bar, z)
    return float(nu @ np.linalg.solve(sigma_bar + Q, nu))


def update(mu_bar, sigma_bar, z, Q):
    K = sigma_bar @ np.linalg.inv(sigma_bar + Q)
    mu = mu_bar + K @ innovation(mu_bar, z)
    mu[2] = wrap(mu[2])
    A = (np.eye(3) - K) @ sigma_bar
    return mu, (A + A.T) / 2


def tuning():
    """The settings of the class challenge: the reference filter's defaults."""
    return {"k_xy": 0.05, "k_theta": 0.05, "c_xy": 90, "field_of_view": 2,
            "lambda": 16.266236196238}
