"""Odometry and how its error grows: a correct solution of the student contract, in Python.

The pose is p = [x, y, theta]; in one step the right wheel rolls ds_r and the left wheel
ds_l metres, b is the wheel base.
"""
import math

import numpy as np


def wrap(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


def step(p, ds_r, ds_l, b):
    """ds, dtheta and the heading halfway through the turn."""
    ds, dtheta = (ds_r + ds_l) / 2, (ds_r - ds_l) / b
    return ds, dtheta, p[2] + dtheta / 2


def odometry_step(p, ds_r, ds_l, b):
    ds, dtheta, phi = step(p, ds_r, ds_l, b)
    return np.array([p[0] + ds * math.cos(phi), p[1] + ds * math.sin(phi),
                     wrap(p[2] + dtheta)])


def pose_jacobian(p, ds_r, ds_l, b):
    ds, _, phi = step(p, ds_r, ds_l, b)
    return np.array([[1, 0, -ds * math.sin(phi)], [0, 1, ds * math.cos(phi)], [0, 0, 1]])


def increment_jacobian(p, ds_r, ds_l, b):
    ds, _, phi = step(p, ds_r, ds_l, b)
    c, s, turn = math.cos(phi) / 2, math.sin(phi) / 2, ds / (2 * b)
    return np.array([[c - turn * math.sin(phi), c + turn * math.sin(phi)],
                     [s + turn * math.cos(phi), s - turn * math.cos(phi)],
                     [1 / b, -1 / b]])


def wheel_noise(ds_r, ds_l, k_r, k_l):
    return np.diag([k_r * abs(ds_r), k_l * abs(ds_l)])


def propagate(Sigma_p, F_p, F_delta, Sigma_delta):
    A = F_p @ Sigma_p @ F_p.T + F_delta @ Sigma_delta @ F_delta.T
    return (A + A.T) / 2
