% Odometry and how its error grows: a correct solution of the student contract, in
% MATLAB, written as the lab's students write: one function after another, each closed
% by `end`. The pose is p = [x; y; theta]; in one step the right wheel rolls ds_r and
% the left wheel ds_l metres, b is the wheel base.

function p_next = odometry_step(p, ds_r, ds_l, b)
  [ds, dtheta, phi] = step(p, ds_r, ds_l, b);
  p_next = [p(1) + ds * cos(phi); p(2) + ds * sin(phi); wrap(p(3) + dtheta)];
end

function F_p = pose_jacobian(p, ds_r, ds_l, b)
  [ds, ~, phi] = step(p, ds_r, ds_l, b);
  F_p = [1, 0, -ds * sin(phi); 0, 1, ds * cos(phi); 0, 0, 1];
end

function F_delta = increment_jacobian(p, ds_r, ds_l, b)
  [ds, ~, phi] = step(p, ds_r, ds_l, b);
  turn = ds / (2 * b);
  F_delta = [cos(phi) / 2 - turn * sin(phi), cos(phi) / 2 + turn * sin(phi);
             sin(phi) / 2 + turn * cos(phi), sin(phi) / 2 - turn * cos(phi);
             1 / b, -1 / b];
end

function Sigma_delta = wheel_noise(ds_r, ds_l, k_r, k_l)
  Sigma_delta = diag([k_r * abs(ds_r), k_l * abs(ds_l)]);
end

function Sigma_p_next = propagate(Sigma_p, F_p, F_delta, Sigma_delta)
  A = F_p * Sigma_p * F_p' + F_delta * Sigma_delta * F_delta';
  Sigma_p_next = (A + A') / 2;
end

% ds, dtheta and the heading halfway through the turn.
function [ds, dtheta, phi] = step(p, ds_r, ds_l, b)
  ds = (ds_r + ds_l) / 2;
  dtheta = (ds_r - ds_l) / b;
  phi = p(3) + dtheta / 2;
end

function a = wrap(a)
  a = mod(a + pi, 2 * pi) - pi;
end
