% The unscented Kalman filter and the particle filter: your implementation.
%
% This is one MATLAB file, run in GNU Octave. Fill in the bodies of the
% functions below and keep their names, arguments and outputs; helper
% functions of your own go in the same file. There is no network and there are
% no files.
% Helper functions of your own are welcome anywhere in the file.
%
% The robot is a unicycle commanded with u = [v, omega] (m/s, rad/s) among
% barcoded posts whose positions are known; its camera reads a post's range
% and bearing, as the robots of the MRCLAM data set do. Your functions are
% called in two ways. The test harness calls each one on generated cases and
% compares what it returns with the reference model (to about 1e-9). The
% filter loop, which is given, strings them into two filters along generated
% robots, after learning the camera's noise Q = measurement_noise(residuals)
% and the control noise's alphas = learn_alphas(commanded, implied):
%   the UKF, at every step
%     R = process_noise(mu, u, dt, alphas)
%     {mu_bar, sigma_bar} = ukf_predict(mu, sigma, u, dt, R)
%     for each reading z of a post at landmark:
%       {mu, sigma, d2} = ukf_update(mu_bar, sigma_bar, z, landmark, Q),
%       kept when d2 <= chi2inv(0.999, 2) (the gate)
%   the particle filter, at every step
%     particles = sample_motion(particles, u, dt, alphas, normals)
%       (unless the robot stands still)
%     weights = particle_weights(particles, weights, z, landmark, Q)
%       for each reading
%     after the step's readings, if there were any and
%       needs_resampling(weights): the particles at
%       low_variance_resample(weights, r), with weights 1/N
%     {mu, sigma} = particle_estimate(particles, weights)
% and the belief at every step must follow the reference filter's. The
% harness gives every random number: the normal draws and the comb's offset.
%
% Conventions
% - A pose is a column [x; y; theta]: metres, and radians wrapped to
%   [-pi, pi). A control is [v, omega], a reading [range, bearing], a
%   post [x, y].
% - Matrices are as MATLAB has them: A(i, j) is row i, column j. A cloud of
%   N particles is N x 3, one pose a row; its weights a vector. Several
%   outputs are declared in the order given below.
% - Here R is the process noise and Q the measurement noise, as in the lab.
% - The state has n = 3 dimensions; the UKF's filter uses alpha = 1,
%   beta = 2, kappa = 1.
% - Every function is pure: it returns new values and keeps nothing between
%   calls, and draws no random numbers of its own.
%
% MATLAB does the linear algebra (A * B, A', inv(A), chol(A, 'lower'): mind
% that chol(A) alone gives the upper factor); a helper you may want to write
% first (at the end of the file):
%   wrap_angle(a)  -> a moved by multiples of 2 pi into [-pi, pi)

% ---- The motion: the unicycle's arc ----
%   pose  [x, y, theta]
%   u     [v, omega], held for dt seconds
% The robot drives an arc of radius v / omega:
%   x' = x + v/omega (-sin(theta) + sin(theta + omega dt))
%   y' = y + v/omega ( cos(theta) - cos(theta + omega dt))
%   theta' = theta + omega dt, wrapped
% and, where omega = 0, the straight line that is its limit:
%   x' = x + v dt cos(theta), y' = y + v dt sin(theta).
% Returns the pose after the step.
function pose = motion(pose, u, dt)
  error('motion: not implemented');
end

% ---- The process noise ----
%   mu, u, dt  as for motion
%   alphas     [a1, a2, a3, a4]: the actual speed's standard deviation is
%              a1 |v| + a2 |omega|, the actual turn rate's a3 |v| + a4 |omega|
% With M = diag((a1 |v| + a2 |omega|)^2, (a3 |v| + a4 |omega|)^2) and V the
% 3 x 2 Jacobian of motion's pose by (v, omega) at mu (its limit where
% omega = 0: d x'/d omega = -v dt^2 sin(theta) / 2, d y'/d omega =
% v dt^2 cos(theta) / 2), returns R = V M V^T, 3 x 3.
function R = process_noise(mu, u, dt, alphas)
  error('process_noise: not implemented');
end

% ---- The sigma points and their weights ----
%   mu, sigma          a belief: 3-vector, 3 x 3
%   alpha, beta, kappa the spread of the points
% With n = 3 and lambda = alpha^2 (n + kappa) - n, and L the lower Cholesky
% factor of (n + lambda) sigma (L L^T = (n + lambda) sigma), the 2n + 1
% points are mu, then mu + each column of L, then mu - each column of L.
% Their weights: for the mean wm = lambda / (n + lambda) for the first and
% 1 / (2 (n + lambda)) for the others; for the covariance the same, but the
% first's is wc = lambda / (n + lambda) + (1 - alpha^2 + beta).
% Returns [X, wm, wc]: X 7 x 3 (a point a row), wm and wc 7 numbers each.
function [X, wm, wc] = sigma_points(mu, sigma, alpha, beta, kappa)
  error('sigma_points: not implemented');
end

% ---- The UKF's prediction ----
%   mu, sigma  the belief after the previous step
%   u, dt      the command and the step's length
%   R          the process noise, from process_noise
% The sigma points of (mu, sigma) (alpha = 1, beta = 2, kappa = 1), each
% moved by motion; mu_bar is their weighted mean, its heading the angle
% atan2(sum wm sin(theta_i), sum wm cos(theta_i)); sigma_bar =
% sum wc d_i d_i^T + R, d_i the point's deviation from mu_bar with its
% heading wrapped; symmetrised, (A + A^T) / 2.
% Returns [mu_bar, sigma_bar].
function [mu_bar, sigma_bar] = ukf_predict(mu, sigma, u, dt, R)
  error('ukf_predict: not implemented');
end

% ---- The UKF's update by a reading ----
%   mu_bar, sigma_bar  the predicted belief
%   z                  the reading [range, bearing]
%   landmark           the post it reads, [x, y]
%   Q                  the camera's noise, 2 x 2
% The sigma points of (mu_bar, sigma_bar), each seen by the camera:
% [sqrt(dx^2 + dy^2), atan2(dy, dx) - theta wrapped], (dx, dy) = landmark -
% the point's position. z_hat is their weighted mean (the bearing averaged
% as an angle); S = sum wc e_i e_i^T + Q, e_i the point's reading minus z_hat
% (bearing wrapped); T = sum wc d_i e_i^T, d_i the point minus mu_bar
% (heading wrapped); K = T S^-1; nu = z - z_hat (bearing wrapped);
%   mu = mu_bar + K nu (heading wrapped), sigma = sigma_bar - K S K^T
% symmetrised, and d2 = nu^T S^-1 nu, for the gate.
% Returns [mu, sigma, d2].
function [mu, sigma, d2] = ukf_update(mu_bar, sigma_bar, z, landmark, Q)
  error('ukf_update: not implemented');
end

% ---- The particles' motion ----
%   particles  N poses
%   u, dt      the command and the step's length
%   alphas     as for process_noise
%   normals    N pairs [n_v, n_omega] of standard normal draws, one a particle
% Particle i drives motion's arc under the control it actually got,
%   [v + (a1 |v| + a2 |omega|) n_v, omega + (a3 |v| + a4 |omega|) n_omega].
% Returns the N moved particles.
function particles = sample_motion(particles, u, dt, alphas, normals)
  error('sample_motion: not implemented');
end

% ---- The particles' weights after a reading ----
%   particles, weights  the cloud
%   z, landmark, Q      as for ukf_update
% Each weight is multiplied by the likelihood of the reading seen from its
% particle, exp(-d_i / 2) with d_i = nu^T Q^-1 nu, nu = z - the particle's
% expected reading (bearing wrapped); then the weights are divided by their
% sum. Use exp(-(d_i - d_min) / 2), d_min the smallest d_i: the division
% cancels the common factor, and far readings then leave no weight at 0/0
% (if the sum is still not a positive number, each weight is 1/N). Returns
% the N new weights.
function weights = particle_weights(particles, weights, z, landmark, Q)
  error('particle_weights: not implemented');
end

% ---- Whether to resample ----
%   weights  N weights that sum to 1
% Returns true when the effective sample size 1 / sum w^2 is below N / 2.
function resample = needs_resampling(weights)
  error('needs_resampling: not implemented');
end

% ---- Low-variance resampling ----
%   weights  N weights that sum to 1
%   r        a uniform draw in [0, 1)
% One comb of N teeth at (r + m) / N, m = 0 .. N-1, laid along the weights:
% tooth m picks the first particle i whose cumulative weight w_0 + ... + w_i
% reaches it (the last particle, where rounding leaves a tooth above the
% total). Returns the N indices picked, in order
% (counted from 1).
function indices = low_variance_resample(weights, r)
  error('low_variance_resample: not implemented');
end

% ---- The cloud's estimate ----
%   particles, weights  the cloud
% mu = sum w_i x_i for x and y, and the heading the angle
% atan2(sum w_i sin(theta_i), sum w_i cos(theta_i)); sigma = sum w_i d_i d_i^T,
% d_i the particle's deviation from mu with its heading wrapped.
% Returns [mu, sigma].
function [mu, sigma] = particle_estimate(particles, weights)
  error('particle_estimate: not implemented');
end

% ---- The camera's noise, learned ----
%   residuals  K readings' errors against the ground truth, [range, bearing]
%              each (bearing wrapped), K x 2
% The maximum-likelihood covariance of a zero-mean Gaussian noise: the mean
% outer product, Q = sum r_k r_k^T / K. Returns Q, 2 x 2.
function Q = measurement_noise(residuals)
  error('measurement_noise: not implemented');
end

% ---- The control noise, learned ----
%   commanded  K commands [v, omega], K x 2
%   implied    beside each, the [v, omega] the ground truth shows the robot
%              drove, K x 2
% For a zero-mean normal error of standard deviation sd, the mean of |e| is
% sd sqrt(2/pi). So fit, by least squares over the K rows,
%   sqrt(pi/2) |v_implied - v|         ~ a1 |v| + a2 |omega|
%   sqrt(pi/2) |omega_implied - omega| ~ a3 |v| + a4 |omega|
% each alpha 0 or more: where a fit's free solution has a negative
% coefficient (or the normal equations have none), fit each of its two terms
% alone, its coefficient clamped at 0, and keep the one whose squared error
% is smaller (the first where they tie). Returns [a1, a2, a3, a4].
function alphas = learn_alphas(commanded, implied)
  error('learn_alphas: not implemented');
end
