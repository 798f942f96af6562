% EKF localization (EL2320 lab): a correct solution of the student contract, in MATLAB,
% with the lab's own signatures and conventions: column vectors, the map M 2 x N, 1-based
% landmark indices, associate's nu, S and H as 2 x N, 2 x 2 x N and 2 x 3 x N, the
% Jacobian's fifth argument (the column of z_hat it reads), and headings of the mean left
% unwrapped by predict and the updates, as the lab's own files leave them. Bearings and
% innovations are wrapped.

function u = calculate_odometry(e_R, e_L, E_T, B, R_R, R_L, delta_t, mu)
  % EL2320 eq. 4, zero at the first step.
  if delta_t == 0
    u = zeros(3, 1);
    return;
  end
  omega_R = 2 * pi * e_R / (E_T * delta_t);
  omega_L = 2 * pi * e_L / (E_T * delta_t);
  v = (omega_R * R_R + omega_L * R_L) / 2;
  omega = (omega_R * R_R - omega_L * R_L) / B;
  u = [v * delta_t * cos(mu(3)); v * delta_t * sin(mu(3)); wrap(omega * delta_t)];
end

function [mu_bar, sigma_bar] = predict(mu, sigma, u, R)
  % EL2320 Alg. 1: mu_bar = mu + u, Sigma_bar = G Sigma G' + R.
  mu_bar = mu + u;
  G = [1, 0, -u(2); 0, 1, u(1); 0, 0, 1];
  sigma_bar = symmetrise(G * sigma * G' + R);
end

function z_hat = observation_model(x, M, j)
  % EL2320 eq. 6: range and bearing of landmark j.
  dx = M(1, j) - x(1);
  dy = M(2, j) - x(2);
  z_hat = [hypot(dx, dy); wrap(atan2(dy, dx) - x(3))];
end

function H = jacobian_observation_model(x, M, j, z_hat, i)
  dx = M(1, j) - x(1);
  dy = M(2, j) - x(2);
  r = z_hat(1, i);
  H = [-dx / r, -dy / r, 0; dy / r^2, -dx / r^2, -1];
end

function [c, outlier, nu, S, H] = associate(mu_bar, sigma_bar, z_i, M, Lambda_M, Q)
  % EL2320 Alg. 2: maximum likelihood over the landmarks, on ln(psi).
  n = size(M, 2);
  nu = zeros(2, n);
  S = zeros(2, 2, n);
  H = zeros(2, 3, n);
  D = zeros(1, n);
  log_psi = zeros(1, n);
  for j = 1:n
    z_hat = observation_model(mu_bar, M, j);
    H(:, :, j) = jacobian_observation_model(mu_bar, M, j, z_hat, 1);
    S(:, :, j) = H(:, :, j) * sigma_bar * H(:, :, j)' + Q;
    nu(:, j) = [z_i(1) - z_hat(1); wrap(z_i(2) - z_hat(2))];
    D(j) = nu(:, j)' * (S(:, :, j) \ nu(:, j));
    log_psi(j) = -0.5 * log(det(2 * pi * S(:, :, j))) - 0.5 * D(j);
  end
  [~, c] = max(log_psi);
  outlier = D(c) >= Lambda_M;
end

function [c, outlier, nu_bar, H_bar] = batch_associate(mu_bar, sigma_bar, z, M, Lambda_M, Q)
  n = size(z, 2);
  c = zeros(1, n);
  outlier = zeros(1, n);
  nu_bar = zeros(2 * n, 1);
  H_bar = zeros(2 * n, 3);
  for i = 1:n
    [c(i), outlier(i), nu, ~, H] = associate(mu_bar, sigma_bar, z(:, i), M, Lambda_M, Q);
    nu_bar(2 * i - 1:2 * i) = nu(:, c(i));
    H_bar(2 * i - 1:2 * i, :) = H(:, :, c(i));
  end
end

function [mu, sigma] = update(mu_bar, sigma_bar, H, S, nu)
  % EL2320 Alg. 3.
  K = sigma_bar * H' / S;
  mu = mu_bar + K * nu;
  sigma = symmetrise((eye(3) - K * H) * sigma_bar);
end

function [mu, sigma] = batch_update(mu_bar, sigma_bar, H_bar, Q_bar, nu_bar)
  % EL2320 Alg. 4, second half.
  S = H_bar * sigma_bar * H_bar' + Q_bar;
  K = sigma_bar * H_bar' / S;
  mu = mu_bar + K * nu_bar;
  sigma = symmetrise((eye(3) - K * H_bar) * sigma_bar);
end

function [mu, sigma, R, Q, Lambda_M] = init(dataset)
  deg = pi / 180;
  R = diag([0.01^2, 0.01^2, deg^2]);
  Q = diag([0.01^2, deg^2]);
  delta_M = 0.999;
  switch dataset
    case 'outliers'
      Q = 0.2^2 * eye(2);
    case 'no-odometry'
      R = eye(3);
      Q = 0.1^2 * eye(2);
      delta_M = 1;
  end
  if delta_M == 1
    Lambda_M = Inf;
  else
    Lambda_M = -2 * log(1 - delta_M);
  end
  mu = zeros(3, 1);
  sigma = 1e-10 * eye(3);
end

function a = wrap(a)
  % An angle wrapped to [-pi, pi).
  a = mod(a + pi, 2 * pi) - pi;
end

function A = symmetrise(A)
  A = (A + A') / 2;
end
