# EKF localization (EL2320 Lab 1): your implementation.
#
# This is one Python 3 file. Fill in the bodies of the functions below and
# keep their names and arguments. NumPy is there (import numpy as np), and the
# standard library's math; there is no network and there are no files.
# Helper functions of your own are welcome anywhere in the file.
#
# Your functions are called in two ways. The test harness calls each one on
# generated cases and compares what it returns with the reference filter (to
# about 1e-9). The filter loop, which is given (you do not write it), strings
# them together on the three data sets: odometry, prediction, then either
# sequential association and update of each reading or batch association and
# update of all readings of a time step, starting from the settings your `init`
# returns.
#
# Conventions
# - Vectors are 1-D NumPy arrays: mu = np.array([x, y, theta]); a function
#   is given arrays, and may return arrays or lists.
# - Matrices are 2-D NumPy arrays: sigma[i, j] is row i, column j. A vector
#   is returned 1-D, not as an n x 1 column.
# - Several outputs are returned as a tuple, in the order given below.
# - The map M is 2 x N: M[0, j] is the x and M[1, j] the y of landmark j.
# - Landmark indices are 0-based: j = 0 .. N-1 (not 1 .. N as in MATLAB).
# - R is the process noise covariance (3 x 3) and Q the measurement noise
#   covariance (2 x 2), as in the lab and Probabilistic Robotics; the lectures
#   swap the letters.
# - Angles are radians, wrapped to [-pi, pi), and so are intermediate ones;
#   lengths are metres, times seconds.
# - Every function is pure: it returns new values and keeps nothing between
#   calls.
#
# NumPy does the linear algebra (A @ B, A.T, np.linalg.inv, np.linalg.det);
# a helper you may want to write first:
#   wrap_angle(a)     -> a moved by multiples of 2 pi into [-pi, pi)
#   symmetrise(A)     -> (A + A.T) / 2, which clears rounding asymmetry from
#                        a covariance

# ---- Odometry (lab eq. 4) ----
# The motion of the robot during the last time step, from the wheel encoders.
#   e_R, e_L   encoder ticks of the right and the left wheel since the previous
#              step
#   E_T        encoder ticks per wheel revolution
#   B          wheel base, the distance between the two wheels (m)
#   R_R, R_L   radius of the right and the left wheel (m)
#   delta_t    time since the previous step (s)
#   mu         the current mean, 3-vector [x, y, theta]; its heading theta
#              turns the distance travelled into x and y components
# Returns u, a 3-vector [dx, dy, dtheta]: the change of the pose in world
# coordinates, dtheta wrapped. At the very first step delta_t is 0 (no time has
# passed, nothing was driven): return [0, 0, 0] then instead of dividing by
# zero.
def calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu):
    raise NotImplementedError("calculate_odometry: not implemented")

# ---- Prediction (lab eq. 5, Algorithm 1) ----
#   mu     3-vector [x, y, theta], the mean after the previous step
#   sigma  3 x 3 covariance
#   u      3-vector from calculate_odometry
#   R      3 x 3 process noise covariance
# Returns mu_bar, sigma_bar:
#   mu_bar     3-vector: mu moved by u, heading wrapped
#   sigma_bar  3 x 3: G sigma G^T + R, where G (3 x 3) is the Jacobian of the
#              motion model with respect to the state; symmetrised
def predict(mu, sigma, u, R):
    raise NotImplementedError("predict: not implemented")

# ---- Observation model (lab eq. 6) ----
# The reading that landmark j would give if the robot stood at pose x.
#   x  3-vector pose [x, y, theta] (the filter passes mu_bar)
#   M  2 x N map
#   j  landmark index, 0-based
# Returns z_hat, a 2-vector [range, bearing]: the distance to the landmark (m)
# and its direction relative to the robot's heading (rad), the bearing wrapped
# to [-pi, pi).
def observation_model(x, M, j):
    raise NotImplementedError("observation_model: not implemented")

# ---- Jacobian of the observation model (lab eq. 6) ----
#   x, M, j  as for observation_model
#   z_hat    observation_model(x, M, j), given so you can reuse its range
# Returns H, 2 x 3: its first row holds the partial derivatives of the range
# with respect to x, y and theta, its second row those of the bearing.
def jacobian_observation_model(x, M, j, z_hat):
    raise NotImplementedError("jacobian_observation_model: not implemented")

# ---- Maximum-likelihood association and outlier test ----
# (Algorithm 2, lab eqs. 7-8)
# Which landmark did one reading most likely come from, and is the reading an
# outlier?
#   mu_bar     3-vector, the predicted mean
#   sigma_bar  3 x 3, the predicted covariance
#   z_i        one reading, 2-vector [range, bearing]
#   M          2 x N map
#   Lambda_M   the outlier threshold on the squared Mahalanobis distance: a
#              number >= 0, or math.inf, which flags nothing (see init)
#   Q          2 x 2 measurement noise covariance
# For every landmark j of the map, with z_hat_j and H_j from the two functions
# above:
#   nu_j  = z_i - z_hat_j                        innovation, bearing wrapped
#   S_j   = H_j sigma_bar H_j^T + Q               innovation covariance, 2 x 2
#   D_j   = nu_j^T S_j^-1 nu_j                    squared Mahalanobis distance
#   psi_j = det(2 pi S_j)^(-1/2) exp(-D_j / 2)    likelihood
# Returns c, outlier, nu, S, H:
#   c        index (0-based) of the landmark with the largest psi_j; on a tie,
#            the lowest such index
#   outlier  True when D_c >= Lambda_M, False otherwise (a boolean)
#   nu       N x 2 array, nu[j] = nu_j
#   S        N x 2 x 2 array, S[j] = S_j
#   H        N x 2 x 3 array, H[j] = H_j
# Every landmark's values are returned, not only the winner's. Tip: when a
# reading is far from every landmark, exp(-D_j / 2) underflows to 0 for all j;
# comparing ln(psi_j) instead keeps the right winner.
def associate(mu_bar, sigma_bar, z_i, M, Lambda_M, Q):
    raise NotImplementedError("associate: not implemented")

# ---- Batch association (Algorithm 4, association part) ----
# All n readings of one time step, each associated as associate does and all
# against the same prediction (no update happens between them).
#   z  2 x n: z[0, i] is the range and z[1, i] the bearing of reading i
#   mu_bar, sigma_bar, M, Lambda_M, Q  as for associate
# Returns c, outlier, nu_bar, H_bar:
#   c        n landmark indices, c[i] for reading i (0-based)
#   outlier  n booleans
#   nu_bar   2n-vector [r_1, b_1, r_2, b_2, ...]: reading i's innovation with
#            landmark c[i], range at 2i and bearing (wrapped) at 2i + 1
#   H_bar    2n x 3: the Jacobians of the chosen landmarks stacked, rows 2i and
#            2i + 1 for reading i
# Include every reading, outliers too: the filter loop drops the outliers'
# entries before it calls batch_update.
def batch_associate(mu_bar, sigma_bar, z, M, Lambda_M, Q):
    raise NotImplementedError("batch_associate: not implemented")

# ---- Sequential update with one reading (Algorithm 3) ----
#   mu_bar     3-vector, the belief so far: the prediction for the first
#              reading of a time step, the previous update's result for the
#              next ones
#   sigma_bar  3 x 3, its covariance
#   H          2 x 3, S 2 x 2, nu 2-vector: associate's H[c], S[c] and nu[c]
# Returns mu, sigma, with the Kalman gain K = sigma_bar H^T S^-1 (3 x 2):
#   mu     3-vector, mu_bar + K nu, heading wrapped
#   sigma  3 x 3, (I - K H) sigma_bar, symmetrised
# The filter loop calls it only for readings that are not outliers.
def update(mu_bar, sigma_bar, H, S, nu):
    raise NotImplementedError("update: not implemented")

# ---- Batch update (Algorithm 4, update part) ----
# One update with the m inlying readings of a time step together.
#   mu_bar     3-vector, the predicted mean
#   sigma_bar  3 x 3, the predicted covariance
#   H_bar      2m x 3, the inliers' Jacobians stacked (batch_associate's rows)
#   Q_bar      2m x 2m, block diagonal with Q in each 2 x 2 diagonal block
#   nu_bar     2m-vector, the inliers' innovations stacked
# Returns mu, sigma: the update of Algorithm 3 with the stacked quantities,
# where the innovation covariance H_bar sigma_bar H_bar^T + Q_bar is 2m x 2m:
# mu is a 3-vector with its heading wrapped, sigma is 3 x 3 and symmetrised.
# The filter loop skips the call when no reading of the step is an inlier. This
# needs the inverse of a 2m x 2m matrix; lab question 9 asks how to get the
# same result inverting only 3 x 3 matrices.
def batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar):
    raise NotImplementedError("batch_update: not implemented")

# ---- Your settings for each data set ----
# The filter loop calls init(dataset) once before the first time step of a run,
# with the name of the data set:
#   "o3"           like the lab's so_o3_ie: an indoor loop past the landmarks,
#                  accurate readings, lightly noisy odometry (sequential
#                  update)
#   "outliers"     like so_pb_10_outlier: a large circle inside a ring of 10
#                  landmarks, noisy readings with some gross outliers, noisy
#                  odometry (sequential update)
#   "no-odometry"  like so_pb_40_no: the same kind of circle with 40 landmarks
#                  and no odometry at all: the encoders never tick, so u is
#                  always zero and R alone must allow for the motion (batch
#                  update, and the sequential one for comparison)
# Returns a dict with the keys mu, sigma, R, Q and Lambda_M:
#   mu        3-vector, the initial mean; every run starts at x = 0, y = 0,
#             theta = 0
#   sigma     3 x 3, the initial covariance; the start is known precisely, so
#             small
#   R         3 x 3 process noise covariance
#   Q         2 x 2 measurement noise covariance
#   Lambda_M  the outlier threshold used by associate and batch_associate:
#             Lambda_M = chi2inv(delta_M, 2) = -2 ln(1 - delta_M), where
#             delta_M is the probability that an inlier passes the test; use
#             math.inf for delta_M = 1, which rejects no reading
# A run passes when every component of its mean absolute error (x, y, theta) is
# below the lab's bound: 0.01 on "o3", 0.06 on "outliers", 0.1 on "no-odometry"
# (batch).
def init(dataset):
    raise NotImplementedError("init: not implemented")
