// The systematic errors view of the odometry page: a robot built otherwise than its
// odometry assumes (E_d, E_b) drives the path, beside the path its odometry computes.
import { byId, setText } from '../controls.js';
import { colours, dashes, line, markers, plane, styled } from '../plots.js';
import { degrees } from './settings.js';
import { View, describeShape, f, show } from './view.js';

/** The series of the systematic plot: the two paths (x, y arrays), their start and ends. */
function systematicSeries([ox, oy] = [[], []], [tx, ty] = [[], []]) {
  const n = ox.length - 1;
  return [
    styled(line('odometry', ox, oy, colours.odometry, { name: "the odometry's path (dotted)" }), dashes.odometry, 2),
    styled(line('truth', tx, ty, colours.truth, { name: "the robot's path (solid)" }), dashes.truth, 1.5),
    markers('start', 'start', n >= 0 ? [[ox[0], oy[0]]] : [], colours.truth, 'triangle', 11),
    markers('ends', 'the ends', n >= 0 ? [[ox[n], oy[n]], [tx[n], ty[n]]] : [], '#1d2125', 'circle', 7),
  ];
}

/** The systematic errors view (#systematic-view): of the page's plots, it draws `systematic`. */
export class SystematicView extends View {
  constructor(estlab, plots) {
    super('systematic', estlab, plots);
  }

  compute(s) {
    const run = this.estlab.odometrySystematic(JSON.stringify(s.params), JSON.stringify(s.errors));
    try {
      return {
        odometry: [0, 1].map((i) => run.odometry(i)),
        truth: [0, 1, 2].map((i) => run.truth(i)),
        finalError: run.finalError(),
      };
    } finally {
      run.free();
    }
  }

  draw(r, s) {
    const { plots } = this;
    const [ox, oy] = r.odometry;
    const [tx, ty] = r.truth;
    const n = ox.length - 1;
    show(plots.systematic, plane(plots.systematic, systematicSeries(r.odometry, r.truth), [ox, tx], [oy, ty]));
    const [dx, dy, dth] = r.finalError;
    const words = `After ${n} steps the robot is ${f(Math.hypot(dx, dy))} m from where its odometry believes it is ` +
      `(Δx = ${f(dx)} m, Δy = ${f(dy)} m) and its heading is off by ${f(dth / degrees)}°, ` +
      `with E_d = ${s.errors.e_d} and E_b = ${s.errors.e_b}.`;
    plots.systematic.describe(`The ${describeShape(s.params.shape)}, as the odometry computes it and as the real robot drives it. ${words}`);
    setText(byId('systematic-summary'), words);
    byId('systematic-summary').dataset.error = JSON.stringify([...r.finalError]);
  }

  /** The view while a drawn path has fewer than two points: empty axes, and what to do. */
  drawNoPath() {
    const { plots } = this;
    show(plots.systematic, plane(plots.systematic, systematicSeries(), [[-1, 5]], [[-1, 5]]));
    plots.systematic.describe('No path yet: draw at least two points.');
    setText(byId('systematic-summary'), 'Draw a path of at least two points on the plot above.');
    delete byId('systematic-summary').dataset.error;
  }
}
