% Fusing odometry with an indoor positioning sensor: your implementation.
%
% This is one MATLAB file, run in GNU Octave. Fill in the bodies of the
% functions below and keep their names, arguments and outputs; helper
% functions of your own go in the same file. There is no network and there are
% no files.
% Helper functions of your own are welcome anywhere in the file.
%
% The sensor is a detector on the ceiling, above the point (0, 0) of the
% room, that sees two infrared platforms on the robot: platform 1 at the
% front, platform 2 at the back. It reports each platform's position and its
% intensity; the brighter a platform, the more precise its position.
%
% Your functions are called in two ways. The test harness calls each one on
% generated cases and compares what it returns with the reference model (to
% about 1e-9). The fusion loop, which is given (you do not write it), strings
% them together over whole trials. From the odometry's first pose it does at
% every step
%   (after the first step)
%   {mu_bar, sigma_bar} = predict(mu, sigma, odom_prev, odom, k_xy, k_theta)
%   and where the detector read the platforms p1, p2:
%   z = combine_platforms(p1, p2)
%   if in_field_of_view(z, radius):
%     Q  = measurement_noise(p1, p2, c_xy)
%     d2 = mahalanobis(mu_bar, sigma_bar, z, Q)
%     if d2 <= lambda (the gate): {mu, sigma} = update(mu_bar, sigma_bar, z, Q)
% and the belief after every step must follow the reference filter's.
% Outside the field of view the sensor is not trusted at all: that is the
% same as a measurement noise Q of infinity, whose gain is zero.
%
% Conventions
% - A pose is a column [x; y; theta]: metres, and radians wrapped to
%   [-pi, pi).
% - A platform's reading is a column [x; y; I]: its position (metres) and its
%   intensity I (> 0).
% - Matrices are as MATLAB has them: A(i, j) is row i, column j. A vector may
%   be returned as a row or a column; several outputs are declared in the
%   order given below: function [mu, sigma] = update(mu_bar, sigma_bar, z, Q).
% - Letters: here, as in the lab, R is the process noise and Q the
%   measurement noise. The Northstar report writes them the other way round.
% - Every function is pure: it returns new values and keeps nothing between
%   calls.
%
% MATLAB does the linear algebra (A * B, A', inv(A), det(A), A \ b); helpers
% you may want to write first (at the end of the file, as functions):
%   wrap_angle(a)     -> a moved by multiples of 2 pi into [-pi, pi)
%   symmetrise(A)     -> (A + A') / 2, which clears rounding asymmetry from a
%                        covariance

% ---- The pose from the two platforms ----
%   p1, p2  the platforms' readings [x, y, I], front one first
% The position is the intensity-weighted mean of the two, with weights
% w_i = I_i / (I_1 + I_2) (they sum to one), and the robot heads along the
% line from platform 2 to platform 1:
%   theta = atan2(y_1 - y_2, x_1 - x_2)
% Returns z, a 3-vector [x, y, theta], theta in [-pi, pi).
function z = combine_platforms(p1, p2)
  error('combine_platforms: not implemented');
end

% ---- The heading's standard deviation, by error propagation ----
%   p1, p2  the platforms' readings [x, y, I]
%   c_xy    the noise constant: platform i's standard deviation in x and in y
%           is sigma_i = c_xy / I_i
% To first order, with the cross terms neglected,
%   sigma_theta^2 = sum over i = 1, 2 of
%                   (d theta / d x_i sigma_i)^2 + (d theta / d y_i sigma_i)^2
% where the partial derivatives are those of theta = atan2(y_1 - y_2,
% x_1 - x_2) by each platform's coordinates. Returns sigma_theta (radians),
% a number.
function sigma_theta = heading_sigma(p1, p2, c_xy)
  error('heading_sigma: not implemented');
end

% ---- The measurement noise ----
%   p1, p2, c_xy  as for heading_sigma
% x and y of the weighted mean take the larger of the two platforms'
% standard deviations, sigma_xy = max(sigma_1, sigma_2); the heading takes
% sigma_theta from heading_sigma; the cross terms are neglected. Returns Q,
% 3 x 3: diag(sigma_xy^2, sigma_xy^2, sigma_theta^2).
function Q = measurement_noise(p1, p2, c_xy)
  error('measurement_noise: not implemented');
end

% ---- The field of view ----
%   z       a measured pose [x, y, theta]
%   radius  the radius of the field of view (m) around the point under the
%           detector, (0, 0)
% Returns true when the pose is at most `radius` from (0, 0) (a pose exactly
% on the edge is in view), false otherwise.
function in_view = in_field_of_view(z, radius)
  error('in_field_of_view: not implemented');
end

% ---- The prediction from the odometry's increment ----
%   mu, sigma     the belief after the previous step: 3-vector, 3 x 3
%   odom_prev     the odometry's own pose at the previous step [x, y, theta]
%   odom          the odometry's own pose now
%   k_xy, k_theta the process noise constants
% The odometry's pose drifts, but its motion from one step to the next is
% good. Its increment, in the frame of the robot at the previous step,
%   (dx, dy) = Rot(-theta_prev) (odom - odom_prev)   (positions only)
%   dtheta   = theta - theta_prev, wrapped
% moves the belief along its own heading:
%   mu_bar = [x + cos(th) dx - sin(th) dy, y + sin(th) dx + cos(th) dy,
%             th + dtheta]   (th = mu's heading; the new heading wrapped)
% with G = d mu_bar / d mu (3 x 3) and, s = sqrt(dx^2 + dy^2),
%   R = diag((k_xy s)^2, (k_xy s)^2, (k_theta (s + |dtheta|))^2)
%   sigma_bar = G sigma G^T + R, symmetrised.
% Returns [mu_bar, sigma_bar].
function [mu_bar, sigma_bar] = predict(mu, sigma, odom_prev, odom, k_xy, ...
    k_theta)
  error('predict: not implemented');
end

% ---- The gate's distance ----
%   mu_bar, sigma_bar  the predicted belief
%   z                  the measured pose
%   Q                  its noise, from measurement_noise
% The sensor measures the whole pose, H = I. With the innovation
% nu = z - mu_bar (its heading wrapped) and S = sigma_bar + Q, returns the
% squared Mahalanobis distance d2 = nu^T S^-1 nu, a number.
function d2 = mahalanobis(mu_bar, sigma_bar, z, Q)
  error('mahalanobis: not implemented');
end

% ---- The update ----
%   mu_bar, sigma_bar, z, Q  as for mahalanobis
% With nu and S as there and the Kalman gain K = sigma_bar S^-1:
%   mu    = mu_bar + K nu, its heading wrapped
%   sigma = (I - K) sigma_bar, symmetrised
% Returns [mu, sigma].
function [mu, sigma] = update(mu_bar, sigma_bar, z, Q)
  error('update: not implemented');
end

% ---- The class challenge: your filter's settings ----
% When you submit, the server also runs your filter over a trial your class
% never sees, with the settings this function returns, and ranks the class by
% the RMS of the position error there (no points: it ranks, it does not
% grade). Tune them on the sensor-fusion page, where "Copy as tuning()" gives
% the sliders' values in this shape; what you tune on one trial may not suit
% another.
%   k_xy, k_theta  the process noise constants predict gets
%   c_xy           the noise constant measurement_noise gets
%   field_of_view  the radius (m) beyond which readings are ignored
%   lambda         the gate on d2: chi2inv(p, 3), 16.2662 for p = 0.999;
%                  Inf for no gate
% These are the reference filter's defaults.
function settings = tuning()
  settings = struct('k_xy', 0.05, 'k_theta', 0.05, 'c_xy', 90, ...
    'field_of_view', 2, 'lambda', 16.266236196238);
end
