// The UMBmark view of the odometry page: the square driven many times each way by the
// robot of the systematic errors, with the wheel noise, and the return errors that
// measure E_max,syst.
import { byId, setText } from '../controls.js';
import { fmt } from '../format.js';
import { colours, dashes, line, markers, outlineSeries, pairs, plane, styled } from '../plots.js';
import { View, f, row, show } from './view.js';

const directionNames = ['clockwise', 'counter-clockwise'];
const directionColours = [colours.estimate, colours.second];

/** The UMBmark view (#umbmark-view): of the page's plots, it draws `umbmark-paths` and `umbmark-errors`. */
export class UmbmarkView extends View {
  constructor(estlab, plots) {
    super('umbmark', estlab, plots);
  }

  compute(s) {
    const test = this.estlab.odometryUmbmark(JSON.stringify(s.params), JSON.stringify(s.errors), JSON.stringify(s.umbmark));
    try {
      return {
        runs: test.runs(),
        directions: [0, 1].map((d) => ({
          odometry: [0, 1].map((i) => test.odometry(d, i)),
          truths: [0, 1].map((i) => test.truths(d, i)),
          errors: [0, 1, 2].map((i) => test.errors(d, i)),
          centre: test.centre(d),
          r: test.r(d),
        })),
        eMax: test.eMaxSyst(),
      };
    } finally {
      test.free();
    }
  }

  draw(u, s) {
    const { plots } = this;
    const [cw, ccw] = u.directions;
    show(plots['umbmark-paths'], plane(plots['umbmark-paths'], [
      styled(line('square cw', cw.odometry[0], cw.odometry[1], colours.odometry, { name: "the odometry's squares (dotted)" }), dashes.odometry, 2),
      styled(line('square ccw', ccw.odometry[0], ccw.odometry[1], colours.odometry, { name: "the odometry's squares (dotted)" }), dashes.odometry, 2),
      line('runs cw', cw.truths[0], cw.truths[1], colours.estimate, { name: 'clockwise runs', lineStyle: { width: 1, color: colours.estimate, opacity: 0.8 } }),
      styled(line('runs ccw', ccw.truths[0], ccw.truths[1], colours.second, { name: 'counter-clockwise runs (dashed)', lineStyle: { width: 1, color: colours.second, opacity: 0.8 } }), dashes.estimate, 1),
      markers('start', 'start', [[0, 0]], colours.truth, 'triangle', 11),
    ], [cw.odometry[0], ccw.odometry[0], cw.truths[0], ccw.truths[0]], [cw.odometry[1], ccw.odometry[1], cw.truths[1], ccw.truths[1]]));

    const circle = [];
    for (let i = 0; i <= 96; i++) circle.push([u.eMax * Math.cos((2 * Math.PI * i) / 96), u.eMax * Math.sin((2 * Math.PI * i) / 96)]);
    const errorSeries = u.directions.flatMap((d, i) => [
      markers(`errors ${i}`, `return errors, ${directionNames[i]}`, pairs(d.errors[0], d.errors[1]), directionColours[i], i === 0 ? 'circle' : 'triangle', 8, 5),
      markers(`centre ${i}`, `centre of gravity, ${directionNames[i]}`, [[...d.centre]], directionColours[i], 'diamond', 16, 7),
    ]);
    show(plots['umbmark-errors'], plane(plots['umbmark-errors'], [
      outlineSeries('e-max', 'E_max,syst round the start (dashed)', [{ coords: circle }], '#5f6b76', 1, 0.8, 2, 'dashed'),
      ...errorSeries,
      markers('origin', 'where every run should end', [[0, 0]], colours.truth, 'triangle', 11, 8),
    ], [cw.errors[0], ccw.errors[0], circle.map((p) => p[0])], [cw.errors[1], ccw.errors[1], circle.map((p) => p[1])]));

    const words = (d, i) => `${directionNames[i]}: centre of gravity (${f(d.centre[0])}, ${f(d.centre[1])}) m, r = ${f(d.r)} m`;
    plots['umbmark-paths'].describe(
      `The ${fmt(s.umbmark.side)} m square driven ${u.runs} times each way with E_d = ${s.errors.e_d}, E_b = ${s.errors.e_b} ` +
      `and the wheel noise above; the odometry believes every run ends at the start. ${words(cw, 0)}; ${words(ccw, 1)}.`);
    const range = (values) => `${f(Math.min(...values))} to ${f(Math.max(...values))}`;
    plots['umbmark-errors'].describe(
      `Return errors (true minus odometry) of ${u.runs} runs each way. Clockwise: x from ${range(cw.errors[0])} m, y from ${range(cw.errors[1])} m. ` +
      `Counter-clockwise: x from ${range(ccw.errors[0])} m, y from ${range(ccw.errors[1])} m. ${words(cw, 0)}; ${words(ccw, 1)}; ` +
      `E_max,syst = ${f(u.eMax)} m.`);
    const body = byId('umbmark-table', HTMLTableElement).tBodies[0];
    body.replaceChildren(...u.directions.map((d, i) => row(directionNames[i], [
      [f(d.centre[0]), d.centre[0]], [f(d.centre[1]), d.centre[1]], [f(d.r), d.r],
    ], directionNames[i])));
    const eMax = byId('e-max');
    setText(eMax, `${f(u.eMax)} m`);
    eMax.dataset.value = String(u.eMax);
  }
}
