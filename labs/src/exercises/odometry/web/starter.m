% Odometry and how its error grows: your implementation.
%
% This is one MATLAB file, run in GNU Octave. Fill in the bodies of the
% functions below and keep their names, arguments and outputs; helper
% functions of your own go in the same file. There is no network and there are
% no files.
% Helper functions of your own are welcome anywhere in the file.
%
% Your functions are called in two ways. The test harness calls each one on
% generated cases and compares what it returns with the reference model (to
% about 1e-9). The path loop, which is given (you do not write it), strings
% them together along two paths, a square driven counter-clockwise and a figure
% eight. It starts at the path's first pose with Sigma_p = 0 (the start is
% known exactly) and at every step, from the wheels' distances of that step,
% does
%   F_p         = pose_jacobian(p, ds_r, ds_l, b)
%   F_delta     = increment_jacobian(p, ds_r, ds_l, b)
%   Sigma_delta = wheel_noise(ds_r, ds_l, k_r, k_l)
%   Sigma_p     = propagate(Sigma_p, F_p, F_delta, Sigma_delta)
%   p           = odometry_step(p, ds_r, ds_l, b)
% and the pose and covariance after every step must follow the reference's.
%
% Conventions
% - The pose is a column p = [x; y; theta]: metres, and radians wrapped to
%   [-pi, pi).
% - In one step the right wheel rolls ds_r and the left wheel ds_l metres; a
%   wheel that rolls backwards has a negative distance. b is the wheel base,
%   the distance between the two wheels (not half of it), in metres.
% - k_r and k_l are the variances of each wheel's distance per metre it rolls
%   (metres).
% - Matrices are as MATLAB has them: A(i, j) is row i, column j. A vector may
%   be returned as a row or a column.
% - Every function is pure: it returns new values and keeps nothing between
%   calls.
%
% MATLAB does the linear algebra (A * B, A', inv(A), det(A), A \ b); helpers
% you may want to write first (at the end of the file, as functions):
%   wrap_angle(a)     -> a moved by multiples of 2 pi into [-pi, pi)
%   symmetrise(A)     -> (A + A') / 2, which clears rounding asymmetry from a
%                        covariance

% ---- One step of odometry ----
% Where the robot is after one step, from where it was and how far each wheel
% rolled.
%   p           3-vector [x, y, theta], the pose before the step
%   ds_r, ds_l  the distances the right and the left wheel rolled (m, signed)
%   b           the wheel base (m)
% With ds = (ds_r + ds_l) / 2, the distance the robot's centre moves, and
% dtheta = (ds_r - ds_l) / b, the change of heading, the robot moves along the
% heading halfway through the turn:
%   p' = p + [ds cos(theta + dtheta/2), ds sin(theta + dtheta/2), dtheta]
% Returns p', a 3-vector [x', y', theta'], theta' wrapped to [-pi, pi).
function p_next = odometry_step(p, ds_r, ds_l, b)
  error('odometry_step: not implemented');
end

% ---- The Jacobian of the step with respect to the pose ----
%   p, ds_r, ds_l, b  as for odometry_step
% Returns F_p = d p' / d p, 3 x 3: row i holds the partial derivatives of the
% i-th component of p' (x', y', theta') with respect to x, y and theta.
function F_p = pose_jacobian(p, ds_r, ds_l, b)
  error('pose_jacobian: not implemented');
end

% ---- The Jacobian of the step with respect to the wheels' distances ----
%   p, ds_r, ds_l, b  as for odometry_step
% Returns F_delta = d p' / d(ds_r, ds_l), 3 x 2: row i holds the partial
% derivatives of the i-th component of p' with respect to ds_r (column 0) and
% ds_l (column 1). Mind that both ds and dtheta depend on each wheel's
% distance.
function F_delta = increment_jacobian(p, ds_r, ds_l, b)
  error('increment_jacobian: not implemented');
end

% ---- The wheels' noise over one step ----
%   ds_r, ds_l  the distances the wheels rolled (m, signed)
%   k_r, k_l    each wheel's distance variance per metre rolled (m)
% Each wheel's error is independent of the other's, and its variance grows in
% proportion to the distance it rolled, forwards or backwards.
% Returns Sigma_delta = diag(k_r |ds_r|, k_l |ds_l|), 2 x 2: the covariance of
% (ds_r, ds_l), the right wheel first.
function Sigma_delta = wheel_noise(ds_r, ds_l, k_r, k_l)
  error('wheel_noise: not implemented');
end

% ---- One step of error propagation ----
%   Sigma_p      3 x 3, the covariance of the pose before the step
%   F_p          3 x 3, from pose_jacobian
%   F_delta      3 x 2, from increment_jacobian
%   Sigma_delta  2 x 2, from wheel_noise
% To first order, the pose's uncertainty is carried through the step by F_p and
% the wheels' is added through F_delta. Returns Sigma_p', 3 x 3: F_p Sigma_p
% F_p^T + F_delta Sigma_delta F_delta^T, symmetrised (it must be exactly
% symmetric).
function Sigma_p_next = propagate(Sigma_p, F_p, F_delta, Sigma_delta)
  error('propagate: not implemented');
end
