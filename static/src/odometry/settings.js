// What the odometry page's controls say, as the library's types read it
// (labs::odometry), the points of a path the reader draws or types, and the
// `estlab odometry` command that makes the same runs.
import { decimal } from '../format.js';

/** Radians in a degree: the controls take degrees, the library radians. */
export const degrees = Math.PI / 180;

/** A log slider's value as it is run: two significant digits (0.05, 0.0001, 0.0032). */
export const twoDigits = (v) => Number(v.toPrecision(2));

/** The points as the text field shows them: `x,y; x,y; ...`. */
export const pointsText = (points) => points.map(([x, y]) => `${x},${y}`).join('; ');

/** Points typed as `x,y; x,y; ...`; throws a message naming the field and the point. */
export function parsePoints(text) {
  const pairs = text.split(';').map((pair) => pair.trim()).filter((pair) => pair !== '');
  return pairs.map((pair, k) => {
    const numbers = pair.split(',').map((v) => (v.trim() === '' ? NaN : Number(v)));
    if (numbers.length !== 2 || !numbers.every(Number.isFinite)) {
      throw new Error(`shape.points: point ${k} must be two numbers x,y, got "${pair}"`);
    }
    return numbers;
  });
}

/** The points without those that repeat the one before (as the library counts them). */
export function distinct(points) {
  return points.filter((p, i) => i === 0 || p[0] !== points[i - 1][0] || p[1] !== points[i - 1][1]);
}

/** The shape the controls (`ui`) say, as `labs::odometry::Shape` reads it; `drawn`: the points drawn. */
function shape(ui, drawn) {
  const kind = ui.shape.value;
  const size = decimal(Number(ui.size.value));
  switch (kind) {
    case 'line': return { kind, length: size };
    case 'circle': return { kind, radius: size, direction: ui.direction.value };
    case 'square': return { kind, side: size, direction: ui.direction.value };
    case 'figure-eight': return { kind, radius: size };
    default: return { kind: 'polyline', points: drawn.map((p) => [...p]) };
  }
}

/**
 * Everything the controls (`ui`) say, with the points drawn (`drawn`), as the library's
 * types read it. Every number is the one the command line gets (decimal: 12 significant
 * digits), so that the command the page shows runs exactly what the page ran.
 */
export function settings(ui, drawn) {
  const sigmaXy = decimal((Number(ui.sigmaXy.value) / 100) ** 2);
  const sigmaTheta = decimal((Number(ui.sigmaTheta.value) * degrees) ** 2);
  const params = {
    shape: shape(ui, drawn),
    speed: twoDigits(ui.speed.value),
    wheel_base: decimal(Number(ui.wheelBase.value)),
    k_r: twoDigits(ui.kR.value),
    k_l: twoDigits(ui.kL.value),
    sigma0: [[sigmaXy, 0, 0], [0, sigmaXy, 0], [0, 0, sigmaTheta]],
  };
  return {
    params,
    robots: Number(ui.robots.value),
    seed: Number(ui.seed.value),
    errors: { e_d: decimal(Number(ui.eD.value)), e_b: decimal(Number(ui.eB.value)) },
    umbmark: { side: decimal(Number(ui.side.value)), runs: Number(ui.runs.value), seed: Number(ui.seed.value) },
  };
}

/** The flags of `estlab odometry` that make the same runs. */
export function commandFlags(s) {
  const p = s.params;
  const flags = [];
  if (p.shape.kind === 'polyline') {
    flags.push('--points', p.shape.points.map(([x, y]) => `${x},${y}`).join(';'));
  } else {
    flags.push('--shape', p.shape.kind, '--size', String(p.shape.length ?? p.shape.radius ?? p.shape.side));
    if (p.shape.direction) flags.push('--direction', p.shape.direction === 'clockwise' ? 'cw' : 'ccw');
  }
  flags.push('--speed', String(p.speed), '--wheel-base', String(p.wheel_base), '--k-r', String(p.k_r), '--k-l', String(p.k_l));
  flags.push('--sigma0', [p.sigma0[0][0], p.sigma0[1][1], p.sigma0[2][2]].map(String).join(','));
  flags.push('--monte-carlo', String(s.robots), '--seed', String(s.seed));
  flags.push('--e-d', String(s.errors.e_d), '--e-b', String(s.errors.e_b));
  flags.push('--umbmark', String(s.umbmark.side), '--runs', String(s.umbmark.runs));
  return flags;
}

/** The command as a person types it: the points quoted for the shell. */
export function commandText(flags) {
  return ['estlab odometry', ...flags.map((flag) => (flag.includes(';') ? `'${flag}'` : flag))].join(' ');
}
