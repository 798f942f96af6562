"""The unscented Kalman filter and the particle filter: a correct solution of the student
contract, in Python with NumPy. A pose is [x, y, theta], a control [v, omega], a reading
[range, bearing], a post [x, y]; a cloud of N particles is N x 3."""
import math

import numpy as np

N = 3


def wrap(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


def motion(pose, u, dt):
    x, y, theta = pose
    v, omega = u
    if omega == 0:
        return np.array([x + v * dt * math.cos(theta), y + v * dt * math.sin(theta), theta])
    turned = theta + omega * dt
    return np.array([x + v / omega * (-math.sin(theta) + math.sin(turned)),
                     y + v / omega * (math.cos(theta) - math.cos(turned)),
                     wrap(turned)])


def control_sd(u, alphas):
    v, omega = abs(u[0]), abs(u[1])
    return alphas[0] * v + alphas[1] * omega, alphas[2] * v + alphas[3] * omega


def process_noise(mu, u, dt, alphas):
    theta = mu[2]
    v, omega = u
    if omega == 0:
        V = np.array([[dt * math.cos(theta), -v * dt**2 * math.sin(theta) / 2],
                      [dt * math.sin(theta), v * dt**2 * math.cos(theta) / 2],
                      [0, dt]])
    else:
        turned = theta + omega * dt
        dsin = -math.sin(theta) + math.sin(turned)
        dcos = math.cos(theta) - math.cos(turned)
        V = np.array([[dsin / omega, -v * dsin / omega**2 + v * dt * math.cos(turned) / omega],
                      [dcos / omega, -v * dcos / omega**2 + v * dt * math.sin(turned) / omega],
                      [0, dt]])
    sd_v, sd_omega = control_sd(u, alphas)
    M = np.diag([sd_v**2, sd_omega**2])
    return V @ M @ V.T


def sigma_points(mu, sigma, alpha, beta, kappa):
    lam = alpha**2 * (N + kappa) - N
    L = np.linalg.cholesky((N + lam) * sigma)
    X = np.vstack([mu, mu + L.T, mu - L.T])
    wm = np.full(2 * N + 1, 1 / (2 * (N + lam)))
    wc = wm.copy()
    wm[0] = lam / (N + lam)
    wc[0] = wm[0] + (1 - alpha**2 + beta)
    return X, wm, wc


def mean_with_angle(points, w, angle):
    mean = w @ points
    mean[angle] = math.atan2(w @ np.sin(points[:, angle]), w @ np.cos(points[:, angle]))
    return mean


def deviations(points, mean, angle):
    d = points - mean
    d[:, angle] = (d[:, angle] + math.pi) % (2 * math.pi) - math.pi
    return d


def ukf_predict(mu, sigma, u, dt, R):
    X, wm, wc = sigma_points(mu, sigma, 1, 2, 1)
    moved = np.array([motion(p, u, dt) for p in X])
    mu_bar = mean_with_angle(moved, wm, 2)
    d = deviations(moved, mu_bar, 2)
    sigma_bar = (d.T * wc) @ d + R
    return mu_bar, (sigma_bar + sigma_bar.T) / 2


def seen(pose, landmark):
    dx, dy = landmark[0] - pose[0], landmark[1] - pose[1]
    return np.array([math.hypot(dx, dy), wrap(math.atan2(dy, dx) - pose[2])])


def ukf_update(mu_bar, sigma_bar, z, landmark, Q):
    X, wm, wc = sigma_points(mu_bar, sigma_bar, 1, 2, 1)
    Z = np.array([seen(p, landmark) for p in X])
    z_hat = mean_with_angle(Z, wm, 1)
    e = deviations(Z, z_hat, 1)
    d = deviations(X, mu_bar, 2)
    S = (e.T * wc) @ e + Q
    T = (d.T * wc) @ e
    S_inv = np.linalg.inv(S)
    K = T @ S_inv
    nu = np.array([z[0] - z_hat[0], wrap(z[1] - z_hat[1])])
    mu = mu_bar + K @ nu
    mu[2] = wrap(mu[2])
    sigma = sigma_bar - K @ S @ K.T
    return mu, (sigma + sigma.T) / 2, float(nu @ S_inv @ nu)


def sample_motion(particles, u, dt, alphas, normals):
    sd_v, sd_omega = control_sd(u, alphas)
    return np.array([motion(p, [u[0] + sd_v * n[0], u[1] + sd_omega * n[1]], dt)
                     for p, n in zip(particles, normals)])


def particle_weights(particles, weights, z, landmark, Q):
    Q_inv = np.linalg.inv(Q)
    d = np.empty(len(particles))
    for i, p in enumerate(particles):
        h = seen(p, landmark)
        nu = np.array([z[0] - h[0], wrap(z[1] - h[1])])
        d[i] = nu @ Q_inv @ nu
    raw = weights * np.exp(-0.5 * (d - d.min()))
    total = raw.sum()
    if not (total > 0 and math.isfinite(total)):
        return np.full(len(weights), 1 / len(weights))
    return raw / total


def needs_resampling(weights):
    return bool(1 / np.sum(weights**2) < len(weights) / 2)


def low_variance_resample(weights, r):
    n = len(weights)
    indices = []
    i, cumulative = 0, weights[0]
    for m in range(n):
        tooth = (r + m) / n
        while tooth > cumulative and i + 1 < n:
            i += 1
            cumulative += weights[i]
        indices.append(i)
    return indices


def particle_estimate(particles, weights):
    mu = mean_with_angle(particles, weights, 2)
    d = deviations(particles, mu, 2)
    return mu, (d.T * weights) @ d


def measurement_noise(residuals):
    return residuals.T @ residuals / len(residuals)


def non_negative_fit(X, y):
    """The least-squares (a, b) of y ~ a x1 + b x2, both 0 or more."""
    A, b = X.T @ X, X.T @ y
    if np.linalg.det(A) != 0:
        ab = np.linalg.solve(A, b)
        if ab[0] >= 0 and ab[1] >= 0:
            return list(ab)
    alone = [max(b[i] / A[i, i], 0) if A[i, i] > 0 else 0 for i in range(2)]
    candidates = [np.array([alone[0], 0.0]), np.array([0.0, alone[1]])]
    sse = [c @ A @ c - 2 * c @ b for c in candidates]
    return list(candidates[0] if sse[0] <= sse[1] else candidates[1])


def learn_alphas(commanded, implied):
    X = np.abs(commanded)
    errors = math.sqrt(math.pi / 2) * np.abs(implied - commanded)
    return non_negative_fit(X, errors[:, 0]) + non_negative_fit(X, errors[:, 1])
