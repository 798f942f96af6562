% Fusing odometry with an indoor positioning sensor: a correct solution of the student
% contract, in MATLAB. A pose is a column [x; y; theta], a platform's reading
% [x; y; I]. Its functions have no closing `end`, as MATLAB's own function files may be
% written, so that the harness splits the file into one function file each.

function z = combine_platforms(p1, p2)
  w1 = p1(3) / (p1(3) + p2(3));
  w2 = p2(3) / (p1(3) + p2(3));
  z = [w1 * p1(1) + w2 * p2(1); w1 * p1(2) + w2 * p2(2);
       atan2(p1(2) - p2(2), p1(1) - p2(1))];

function sigma_theta = heading_sigma(p1, p2, c_xy)
  s1 = c_xy / p1(3);
  s2 = c_xy / p2(3);
  sigma_theta = sqrt(s1^2 + s2^2) / hypot(p1(1) - p2(1), p1(2) - p2(2));

function Q = measurement_noise(p1, p2, c_xy)
  sxy = max(c_xy / p1(3), c_xy / p2(3));
  Q = diag([sxy^2, sxy^2, heading_sigma(p1, p2, c_xy)^2]);

function in_view = in_field_of_view(z, radius)
  in_view = hypot(z(1), z(2)) <= radius;

function [mu_bar, sigma_bar] = predict(mu, sigma, odom_prev, odom, k_xy, k_theta)
  % The odometry's increment in the frame of its previous pose, applied along the
  % belief's own heading.
  c0 = cos(odom_prev(3));
  s0 = sin(odom_prev(3));
  g = odom(1:2) - odom_prev(1:2);
  d = [c0, s0; -s0, c0] * g;
  dtheta = wrap(odom(3) - odom_prev(3));
  c = cos(mu(3));
  s = sin(mu(3));
  mu_bar = [mu(1) + c * d(1) - s * d(2); mu(2) + s * d(1) + c * d(2); wrap(mu(3) + dtheta)];
  G = [1, 0, -s * d(1) - c * d(2); 0, 1, c * d(1) - s * d(2); 0, 0, 1];
  moved = norm(d);
  R = diag([(k_xy * moved)^2, (k_xy * moved)^2, (k_theta * (moved + abs(dtheta)))^2]);
  A = G * sigma * G' + R;
  sigma_bar = (A + A') / 2;

function d2 = mahalanobis(mu_bar, sigma_bar, z, Q)
  nu = innovation(mu_bar, z);
  d2 = nu' * ((sigma_bar + Q) \ nu);

function [mu, sigma] = update(mu_bar, sigma_bar, z, Q)
  K = sigma_bar / (sigma_bar + Q);
  mu = mu_bar + K * innovation(mu_bar, z);
  mu(3) = wrap(mu(3));
  A = (eye(3) - K) * sigma_bar;
  sigma = (A + A') / 2;

function settings = tuning()
  % The settings of the class challenge: the reference filter's defaults.
  settings = struct('k_xy', 0.05, 'k_theta', 0.05, 'c_xy', 90, 'field_of_view', 2, ...
                    'lambda', 16.266236196238);

function nu = innovation(mu, z)
  nu = z(:) - mu(:);
  nu(3) = wrap(nu(3));

function a = wrap(a)
  a = mod(a + pi, 2 * pi) - pi;
