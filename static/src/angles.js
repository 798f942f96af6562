// Angles as the estimators keep them.

/** An angle moved by whole turns into [-pi, pi). */
export const wrap = (angle) => angle - 2 * Math.PI * Math.floor((angle + Math.PI) / (2 * Math.PI));
