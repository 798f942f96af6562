% The unscented Kalman filter and the particle filter: a correct solution of the student
% contract, in MATLAB. A pose is a column [x; y; theta], a control [v; omega], a reading
% [range; bearing], a post [x; y]; a cloud of N particles is N x 3, a pose a row, and its
% weights a column.

function pose = motion(pose, u, dt)
  x = pose(1); y = pose(2); theta = pose(3);
  v = u(1); omega = u(2);
  if omega == 0
    pose = [x + v * dt * cos(theta); y + v * dt * sin(theta); theta];
  else
    turned = theta + omega * dt;
    pose = [x + v / omega * (-sin(theta) + sin(turned));
            y + v / omega * (cos(theta) - cos(turned));
            wrap_angle(turned)];
  end
end

function R = process_noise(mu, u, dt, alphas)
  theta = mu(3);
  v = u(1); omega = u(2);
  if omega == 0
    V = [dt * cos(theta), -v * dt^2 * sin(theta) / 2;
         dt * sin(theta), v * dt^2 * cos(theta) / 2;
         0, dt];
  else
    turned = theta + omega * dt;
    dsin = -sin(theta) + sin(turned);
    dcos = cos(theta) - cos(turned);
    V = [dsin / omega, -v * dsin / omega^2 + v * dt * cos(turned) / omega;
         dcos / omega, -v * dcos / omega^2 + v * dt * sin(turned) / omega;
         0, dt];
  end
  sd = control_sd(u, alphas);
  R = V * diag(sd .^ 2) * V';
end

function [X, wm, wc] = sigma_points(mu, sigma, alpha, beta, kappa)
  n = 3;
  lambda = alpha^2 * (n + kappa) - n;
  L = chol((n + lambda) * sigma, 'lower');
  mu = mu(:)';
  X = [mu; mu + L'; mu - L'];
  wm = repmat(1 / (2 * (n + lambda)), 2 * n + 1, 1);
  wc = wm;
  wm(1) = lambda / (n + lambda);
  wc(1) = wm(1) + (1 - alpha^2 + beta);
end

function [mu_bar, sigma_bar] = ukf_predict(mu, sigma, u, dt, R)
  [X, wm, wc] = sigma_points(mu, sigma, 1, 2, 1);
  moved = zeros(size(X));
  for i = 1:rows(X)
    moved(i, :) = motion(X(i, :)', u, dt)';
  end
  mu_bar = angle_mean(moved, wm, 3);
  d = angle_deviations(moved, mu_bar, 3);
  sigma_bar = d' * (d .* wc) + R;
  sigma_bar = (sigma_bar + sigma_bar') / 2;
end

function [mu, sigma, d2] = ukf_update(mu_bar, sigma_bar, z, landmark, Q)
  [X, wm, wc] = sigma_points(mu_bar, sigma_bar, 1, 2, 1);
  Z = zeros(rows(X), 2);
  for i = 1:rows(X)
    Z(i, :) = seen(X(i, :), landmark)';
  end
  z_hat = angle_mean(Z, wm, 2);
  e = angle_deviations(Z, z_hat, 2);
  d = angle_deviations(X, mu_bar, 3);
  S = e' * (e .* wc) + Q;
  T = d' * (e .* wc);
  K = T / S;
  nu = [z(1) - z_hat(1); wrap_angle(z(2) - z_hat(2))];
  mu = mu_bar(:) + K * nu;
  mu(3) = wrap_angle(mu(3));
  sigma = sigma_bar - K * S * K';
  sigma = (sigma + sigma') / 2;
  d2 = nu' * (S \ nu);
end

function particles = sample_motion(particles, u, dt, alphas, normals)
  sd = control_sd(u, alphas);
  for i = 1:rows(particles)
    drawn = [u(1) + sd(1) * normals(i, 1); u(2) + sd(2) * normals(i, 2)];
    particles(i, :) = motion(particles(i, :)', drawn, dt)';
  end
end

function weights = particle_weights(particles, weights, z, landmark, Q)
  d = zeros(rows(particles), 1);
  for i = 1:rows(particles)
    h = seen(particles(i, :), landmark);
    nu = [z(1) - h(1); wrap_angle(z(2) - h(2))];
    d(i) = nu' * (Q \ nu);
  end
  raw = weights(:) .* exp(-0.5 * (d - min(d)));
  total = sum(raw);
  if total > 0 && isfinite(total)
    weights = raw / total;
  else
    weights = repmat(1 / numel(weights), numel(weights), 1);
  end
end

function resample = needs_resampling(weights)
  resample = 1 / sum(weights .^ 2) < numel(weights) / 2;
end

function indices = low_variance_resample(weights, r)
  n = numel(weights);
  indices = zeros(n, 1);
  i = 1;
  cumulative = weights(1);
  for m = 0:n - 1
    tooth = (r + m) / n;
    while tooth > cumulative && i < n
      i = i + 1;
      cumulative = cumulative + weights(i);
    end
    indices(m + 1) = i;
  end
end

function [mu, sigma] = particle_estimate(particles, weights)
  mu = angle_mean(particles, weights(:), 3);
  d = angle_deviations(particles, mu, 3);
  sigma = d' * (d .* weights(:));
end

function Q = measurement_noise(residuals)
  Q = residuals' * residuals / rows(residuals);
end

function alphas = learn_alphas(commanded, implied)
  X = abs(commanded);
  errors = sqrt(pi / 2) * abs(implied - commanded);
  alphas = [non_negative_fit(X, errors(:, 1)); non_negative_fit(X, errors(:, 2))];
end

% The helpers.

% The least-squares [a; b] of y ~ a x1 + b x2, both 0 or more.
function ab = non_negative_fit(X, y)
  A = X' * X;
  b = X' * y;
  if det(A) ~= 0
    ab = A \ b;
    if all(ab >= 0)
      return;
    end
  end
  alone = zeros(2, 1);
  for i = 1:2
    if A(i, i) > 0
      alone(i) = max(b(i) / A(i, i), 0);
    end
  end
  first = [alone(1); 0];
  second = [0; alone(2)];
  if first' * A * first - 2 * first' * b <= second' * A * second - 2 * second' * b
    ab = first;
  else
    ab = second;
  end
end

function sd = control_sd(u, alphas)
  sd = [alphas(1) * abs(u(1)) + alphas(2) * abs(u(2));
        alphas(3) * abs(u(1)) + alphas(4) * abs(u(2))];
end

function h = seen(pose, landmark)
  dx = landmark(1) - pose(1);
  dy = landmark(2) - pose(2);
  h = [hypot(dx, dy); wrap_angle(atan2(dy, dx) - pose(3))];
end

% The weighted mean of the rows of `points`, column `angle` averaged as an angle.
function m = angle_mean(points, w, angle)
  m = (w' * points)';
  m(angle) = atan2(w' * sin(points(:, angle)), w' * cos(points(:, angle)));
end

% The rows of `points` less `m`, column `angle` wrapped.
function d = angle_deviations(points, m, angle)
  d = points - m(:)';
  d(:, angle) = wrap_angle(d(:, angle));
end

function a = wrap_angle(a)
  a = mod(a + pi, 2 * pi) - pi;
end
