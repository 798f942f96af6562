// The rough edges a student met (issue 22), in headless Chromium against the real server,
// each at a phone's size and a laptop's: /ekf keeps only the settings the reader changed
// when the data set changes, its address follows the run and opens it again, and a
// setting out of range is refused beside its field; after Run tests the workbench says
// the score under the button, announces it and brings the results into view, its editor
// wraps lines and the starters fit 80 columns; legends wrap instead of paging, with an
// icon per line style; equations too wide say they scroll and take the keyboard; the
// /ekf map uses a phone's height; /odometry says what is wrong beside the field; a
// stale run's plots keep their text legible; the result panels have no empty headers or
// skipped heading levels.
import assert from 'node:assert/strict';
import { readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import {
  bounded, exercisesDir, laptop, openPage, phone, root, runAndWait, setUpCourse, signIn, startServer, starterOf,
  typeInEditor, withServerAndBrowser,
} from './harness.mjs';

let server;
let browser;
withServerAndBrowser((started, launched) => {
  server = started;
  browser = launched;
});

const sizes = [['phone', phone], ['laptop', laptop]];

/** The page's command-line flags (those of the run shown), or null with no run shown. */
async function flags(page) {
  const text = await page.locator('#command').getAttribute('data-flags');
  return text ? JSON.parse(text) : null;
}

/** Picks `kind` in /ekf's data set list and waits for its run (or its refusal). */
async function pickKind(page, kind) {
  await page.locator('#dataset-kind').selectOption(kind);
  await page.waitForFunction((k) => new URLSearchParams(location.search).get('kind') === k, kind);
}

/** The lab's flags of each data set, as /ekf opens it. */
const labFlags = {
  o3: ['--R', '0.0001,0.0001,0.000304617419787', '--Q', '0.0001,0.000304617419787', '--delta-m', '0.999'],
  outliers: ['--R', '0.0001,0.0001,0.000304617419787', '--Q', '0.04,0.04', '--delta-m', '0.999'],
  'no-odometry': ['--R', '1,1,1', '--Q', '0.01,0.01', '--delta-m', '1', '--batch'],
};

/**
 * Where `input`'s message is: the note that describes the field (aria-describedby), its
 * text, and how far below the field it starts, in pixels.
 */
function messageOf(page, input) {
  return page.evaluate((selector) => {
    const field = document.querySelector(selector);
    const ids = (field.getAttribute('aria-describedby') ?? '').split(' ').filter(Boolean);
    const note = ids.map((id) => document.getElementById(id)).find((el) => el && !el.hidden && el.textContent);
    if (!note) return { invalid: field.getAttribute('aria-invalid'), text: null };
    const [a, b] = [field.getBoundingClientRect(), note.getBoundingClientRect()];
    return { invalid: field.getAttribute('aria-invalid'), text: note.textContent, below: b.top - a.bottom, visible: b.height > 0 };
  }, input);
}

for (const [size, viewport] of sizes) {
  test(`/ekf at the ${size}'s size: another data set keeps only the settings the reader changed`, bounded, async () => {
    const page = await openPage(browser, `${server.url}/ekf`, viewport);
    const note = page.locator('#settings-note');
    // The update changed alone: it stays, and R, Q and δ_M become the new data's.
    await page.locator('input[name=mode][value=batch]').check();
    assert.deepEqual(await flags(page), [...labFlags.o3, '--batch']);
    await pickKind(page, 'outliers');
    assert.deepEqual(await flags(page), [...labFlags.outliers, '--batch']);
    assert.equal(await note.textContent(),
      "Your settings, kept when the data set changed: the update differs from the lab's settings for outliers; the button “the lab's settings” sets those.");
    // One σ of R typed: it alone stays; the rest of R, Q and δ_M follow the data.
    await page.locator('#lab-settings').click();
    await page.locator('#r-x').fill('0.05');
    await pickKind(page, 'no-odometry');
    assert.equal(await page.locator('#r-x').inputValue(), '0.05');
    assert.deepEqual(await flags(page), ['--R', '0.0025,1,1', '--Q', '0.01,0.01', '--delta-m', '1', '--batch']);
    // A setting typed back to the lab's value is no change: it follows the data again.
    await page.locator('#r-x').fill('1');
    await pickKind(page, 'o3');
    assert.deepEqual(await flags(page), labFlags.o3);
    assert.equal(await note.textContent(), "These are the lab's settings for o3.");
    assert.deepEqual(page.problems, []);
    await page.close();
  });

  test(`/ekf at the ${size}'s size: the address follows the run, and a link opens the same run`, bounded, async () => {
    const page = await openPage(browser, `${server.url}/ekf`, viewport);
    assert.equal(new URL(page.url()).search, '?kind=o3&seed=1');
    await pickKind(page, 'outliers');
    await page.locator('#dataset-seed').fill('4');
    await page.locator('#dataset-seed').dispatchEvent('change');
    await page.locator('#q-range').fill('0.3');
    await page.locator('#delta-m').fill('0.95');
    await page.locator('#known-associations').check();
    const address = new URL(page.url());
    assert.deepEqual(Object.fromEntries(address.searchParams),
      { kind: 'outliers', seed: '4', 'q-range': '0.3', 'delta-m': '0.95', 'known-associations': 'true' });
    const [command, summary] = [await page.locator('#command').textContent(), await page.locator('#summary').textContent()];
    assert.match(command, /--kind outliers --seed 4 .*--Q 0\.09,0\.04 --delta-m 0\.95 --known-associations$/);
    // Opened elsewhere, the link runs the same: the same command, the same numbers.
    const shared = await openPage(browser, address.href, viewport);
    assert.equal(await shared.locator('#command').textContent(), command);
    assert.equal(await shared.locator('#summary').textContent(), summary);
    assert.equal(await shared.locator('#q-range').inputValue(), '0.3');
    assert.match(await shared.locator('#settings-note').textContent(), /^Your own settings: Q, δ_M, known associations differ/);
    // The link's settings are the reader's own: they stay on another data set.
    await pickKind(shared, 'o3');
    assert.deepEqual(await flags(shared), ['--R', '0.0001,0.0001,0.000304617419787', '--Q', '0.09,0.000304617419787',
      '--delta-m', '0.95', '--known-associations']);
    // The workbench's links to its graded runs name the update: it is read as before.
    const graded = await openPage(browser, `${server.url}/ekf?kind=no-odometry&seed=2&mode=sequential`, viewport);
    assert.deepEqual(await flags(graded), ['--R', '1,1,1', '--Q', '0.01,0.01', '--delta-m', '1']);
    assert.equal(new URL(graded.url()).search, '?kind=no-odometry&seed=2&mode=sequential');
    assert.deepEqual([...page.problems, ...shared.problems, ...graded.problems], []);
    await graded.close();
    await shared.close();
    await page.close();
  });

  test(`/ekf at the ${size}'s size: a setting out of range is refused beside its field and runs nothing`, bounded, async () => {
    const page = await openPage(browser, `${server.url}/ekf`, viewport);
    const good = await flags(page);
    const cases = [
      ['#r-x', '-0.1', /must be a number above 0 \(in metres\), got -0\.1/],
      ['#q-bearing', '0', /must be a number above 0 \(in degrees\), got 0/],
      ['#delta-m', '1.5', /a number in \(0, 1\], got 1\.5/],
      ['#delta-m', '0', /a number in \(0, 1\], got 0/],
    ];
    for (const [input, value, message] of cases) {
      await page.locator(input).fill(value);
      const shown = await messageOf(page, input);
      assert.equal(shown.invalid, 'true', `${input} = ${value}`);
      assert.match(shown.text ?? '', message);
      assert.ok(shown.visible && shown.below >= -2 && shown.below < 40, `${input}: the message lies right under the field (${shown.below} px)`);
      assert.equal(await flags(page), null, `${input} = ${value} runs nothing`);
      assert.equal(await page.locator('#summary').isVisible(), false);
      assert.match(await page.locator('#stale').textContent(), /No run: a setting is out of range/);
      if (input === '#delta-m') assert.equal(await page.locator('#lambda-m').textContent(), '', 'no Λ_M of a δ_M out of range');
      // Back to a good value: the message goes, the run comes back.
      await page.locator(input).fill(input === '#delta-m' ? '0.999' : '0.01');
      assert.equal((await messageOf(page, input)).invalid, null);
      assert.notEqual(await flags(page), null);
    }
    await page.locator('#lab-settings').click();
    assert.deepEqual(await flags(page), good);
    // A link with a setting out of range: refused the same way, as it opens.
    const linked = await openPage(browser, `${server.url}/ekf?kind=o3&seed=1&r-theta=-2`, viewport);
    assert.equal(await linked.locator('#r-theta').inputValue(), '-2');
    assert.match((await messageOf(linked, '#r-theta')).text, /got -2/);
    assert.equal(await flags(linked), null);
    await linked.locator('#r-theta').fill('2');
    await linked.waitForFunction(() => document.getElementById('command').dataset.flags);
    assert.deepEqual([...page.problems, ...linked.problems], []);
    await linked.close();
    await page.close();
  });
}

// ---------------------------------------------------------------------------------------
// The workbenches.

/** The lines of a starter file longer than 80 columns. */
function longLines(file) {
  return readFileSync(file, 'utf8').split('\n')
    .map((line, i) => [i + 1, line.length]).filter(([, length]) => length > 80);
}

test('every exercise\'s starter fits 80 columns', () => {
  const folders = readdirSync(exercisesDir, { withFileTypes: true }).filter((entry) => entry.isDirectory());
  assert.ok(folders.length >= 2);
  for (const { name } of folders) assert.deepEqual(longLines(starterOf(name)), [], name);
});

for (const [size, viewport] of sizes) {
  for (const path of ['/ekf/code', '/odometry/code', '/fusion/code']) {
    test(`${path} at the ${size}'s size: after Run tests the score is said under the button, announced, and the results are in view`, bounded, async () => {
      const page = await openPage(browser, server.url + path, viewport);
      // The editor wraps its lines: nothing to scroll sideways, at any width.
      const editor = await page.evaluate(() => {
        const content = document.querySelector('#editor .cm-content');
        const scroller = document.querySelector('#editor .cm-scroller');
        return {
          wraps: content.classList.contains('cm-lineWrapping'),
          sideways: scroller.scrollWidth - scroller.clientWidth,
          name: content.getAttribute('aria-label'),
          tabindex: content.getAttribute('tabindex'),
        };
      });
      assert.deepEqual(editor, { wraps: true, sideways: 0, name: 'your code', tabindex: '0' });
      await runAndWait(page, '#run-tests');
      const summary = page.locator('#run-summary');
      await summary.waitFor({ state: 'visible' });
      assert.equal(await summary.getAttribute('role'), 'status');
      assert.match(await summary.textContent(), /^Done\. In your browser: 0 of \d+ points \(0%\), 0 of \d+ tests pass/);
      const [button, said] = [await page.locator('#run-tests').boundingBox(), await summary.boundingBox()];
      assert.ok(said.y >= button.y + button.height && said.y - (button.y + button.height) < 60, 'the summary lies under the button');
      // The results (their status and score first) are on the screen.
      const results = await page.evaluate(() => {
        const box = document.getElementById('score').getBoundingClientRect();
        return { top: box.top, bottom: box.bottom, height: window.innerHeight };
      });
      assert.ok(results.top >= 0 && results.bottom <= results.height, `the score is in view: ${JSON.stringify(results)}`);
      assert.deepEqual(page.problems, []);
      await page.close();
    });
  }
}

// ---------------------------------------------------------------------------------------
// Plots and equations.

/**
 * Every drawn plot's legend on the page: its type, its entries, and where ECharts drew
 * it against the plot area and the chart's width.
 */
function legends(page) {
  return page.evaluate(() => [...document.querySelectorAll('figure.plot .chart')].flatMap((element) => {
    const { plot } = element;
    if (!element.getClientRects().length) return [];
    plot.flush();
    const option = plot.chart.getOption();
    const legend = option.legend?.[0];
    if (!legend || legend.show === false) return [];
    const model = plot.chart.getModel().getComponent('legend');
    const group = plot.chart.getViewOfComponentModel(model).group;
    const rect = group.getBoundingRect();
    return [{
      plot: element.closest('figure').dataset.name,
      type: legend.type,
      entries: legend.data,
      top: group.y + rect.y,
      bottom: group.y + rect.y + rect.height,
      right: group.x + rect.x + rect.width,
      width: plot.chart.getWidth(),
      gridTop: option.grid[0].top,
    }];
  }));
}

for (const [size, viewport] of sizes) {
  test(`legends at the ${size}'s size wrap above the plot, with an icon per line style`, bounded, async () => {
    for (const path of ['/ekf', '/odometry', '/car', '/fusion']) {
      const page = await openPage(browser, server.url + path, viewport);
      if (path === '/car') {
        await page.locator('#runs').fill('20');
        await page.locator('#monte-carlo').check();
      }
      for (const figure of await page.locator('figure.plot').all()) await figure.scrollIntoViewIfNeeded();
      const shown = await legends(page);
      assert.ok(shown.length >= 3, `${path}: legends drawn: ${shown.length}`);
      for (const legend of shown) {
        const what = `${path} ${legend.plot}`;
        assert.equal(legend.type, 'plain', `${what}: no paged legend`);
        assert.ok(legend.bottom <= legend.gridTop, `${what}: the legend (to ${legend.bottom} px) ends above the plot area (${legend.gridTop} px)`);
        assert.ok(legend.right <= legend.width, `${what}: the legend fits the chart's width`);
      }
      // A solid line and a dashed one have different icons, drawn in their style.
      const map = shown.find((legend) => legend.plot === ({ '/car': 'spread', '/ekf': 'map', '/fusion': 'map' }[path] ?? 'path'));
      const icons = new Set(map.entries.filter((entry) => entry.icon?.startsWith('path://')).map((entry) => entry.icon));
      assert.ok(icons.size >= 2, `${path}: line styles with icons of their own: ${JSON.stringify(map.entries)}`);
      assert.deepEqual(page.problems, []);
      await page.close();
    }
  });
}

test('at a phone\'s size an equation wider than its box shows it scrolls, and the keyboard scrolls it', bounded, async () => {
  for (const [size, viewport] of sizes) {
    for (const path of ['/car', '/ekf', '/odometry', '/fusion']) {
      const page = await openPage(browser, server.url + path, viewport);
      const boxes = await page.evaluate(() => [...document.querySelectorAll('.katex-display')].map((box) => ({
        wide: box.scrollWidth > box.clientWidth + 1,
        marked: box.classList.contains('scrolls'),
        tabindex: box.getAttribute('tabindex'),
        label: box.getAttribute('aria-label'),
        shadow: getComputedStyle(box).backgroundImage.includes('gradient'),
      })));
      for (const [i, box] of boxes.entries()) {
        const what = `${path} at the ${size}'s size, equation ${i}`;
        assert.equal(box.marked, box.wide, `${what}: marked as scrolling exactly when it is too wide`);
        assert.equal(box.tabindex, box.wide ? '0' : null, what);
        assert.equal(box.shadow, box.wide, `${what}: a shadow at the edge says there is more`);
        if (box.wide) assert.equal(box.label, 'equation, scrolls sideways', what);
      }
      if (size === 'phone') {
        const wide = boxes.findIndex((box) => box.wide);
        assert.ok(wide >= 0, `${path}: some equation is wider than a phone`);
        const box = page.locator('.katex-display').nth(wide);
        await box.focus();
        await page.keyboard.press('ArrowRight');
        await page.waitForFunction((i) => document.querySelectorAll('.katex-display')[i].scrollLeft > 0, wide);
      }
      assert.deepEqual(page.problems, []);
      await page.close();
    }
  }
});

test('on a phone the /ekf map uses the screen\'s height, not a thin strip', bounded, async () => {
  for (const [size, viewport] of sizes) {
    const page = await openPage(browser, `${server.url}/ekf`, viewport);
    await page.locator('figure[data-name="map"]').scrollIntoViewIfNeeded();
    const map = await page.evaluate(() => {
      const { plot } = document.querySelector('figure[data-name="map"] .chart');
      plot.flush();
      const { chart, grid } = plot;
      // The landmarks and the paths, in pixels: how much of the plot area they fill.
      const points = plot.series().filter((s) => ['landmarks', 'true', 'odometry only'].includes(s.id)).flatMap((s) => s.data);
      const ys = points.map((point) => chart.convertToPixel({ gridIndex: 0 }, point)[1]);
      const area = chart.getHeight() - grid.top - grid.bottom;
      return { height: chart.getHeight(), filled: (Math.max(...ys) - Math.min(...ys)) / area, screen: window.innerHeight };
    });
    assert.ok(map.height >= 0.55 * map.screen || map.height >= 560, `${size}: the map is ${map.height} px high on a screen of ${map.screen}`);
    // On a phone o3's long room is turned to run up the screen; a laptop has the width.
    if (size === 'phone') {
      assert.ok(map.filled >= 0.6, `${size}: the data fill ${Math.round(100 * map.filled)} % of the map's height`);
      assert.equal(await page.locator('#map-turned').isVisible(), true);
      // The phone turned on its side: the map is wider than tall again, and not turned.
      await page.setViewportSize({ width: phone.height, height: phone.width });
      await page.locator('#map-turned').waitFor({ state: 'hidden' });
      // A plot out of view draws only once it is seen again: where the new width leaves
      // the map, look at it (as the reader would), then wait for the drawing, not a time.
      await page.locator('figure[data-name="map"]').scrollIntoViewIfNeeded();
      // (A function, not a string: the page's CSP refuses a string evaluated as code.)
      const xAxisName = () => document.querySelector('figure[data-name="map"] .chart').plot.chart.getOption().xAxis[0].name;
      await page.waitForFunction((name) => document.querySelector('figure[data-name="map"] .chart').plot.chart.getOption().xAxis[0].name === name, 'x (m)');
      assert.equal(await page.evaluate(xAxisName), 'x (m)');
    } else {
      assert.equal(await page.locator('#map-turned').isVisible(), false);
    }
    assert.deepEqual(page.problems, []);
    await page.close();
  }
});

// ---------------------------------------------------------------------------------------
// Messages beside their fields, legible stale plots, and the result panels' structure.

for (const [size, viewport] of sizes) {
  test(`/odometry at the ${size}'s size: a bad point or field is said beside it`, bounded, async () => {
    const page = await openPage(browser, `${server.url}/odometry`, viewport);
    await page.locator('#shape').selectOption('polyline');
    await page.locator('#points').fill('0,0; 3');
    let shown = await messageOf(page, '#points');
    assert.equal(shown.invalid, 'true');
    assert.equal(shown.text, 'shape.points: point 1 must be two numbers x,y, got "3"');
    assert.ok(shown.visible && shown.below >= -2 && shown.below < 40, `the message lies under the field (${shown.below} px)`);
    await page.locator('#points').fill('0,0; 3,0; 3,2');
    assert.equal((await messageOf(page, '#points')).text, null);
    await page.locator('#shape').selectOption('square');
    const fields = [['#size', '0', '4', /^shape\.side: must lie in/], ['#robots', '1', '1000', /^robots: must lie in 2\.\./],
      ['#umbmark-runs', '0', '5', /^runs: must lie in/]];
    for (const [input, bad, good, message] of fields) {
      await page.locator(input).fill(bad);
      shown = await messageOf(page, input);
      assert.match(shown.text ?? '', message, input);
      assert.ok(shown.visible && shown.below >= -2 && shown.below < 40, `${input}: the message lies under the field (${shown.below} px)`);
      await page.locator(input).fill(good);
      assert.equal((await messageOf(page, input)).invalid, null, `${input}: the message goes with the mistake`);
    }
    assert.deepEqual(page.problems, []);
    await page.close();
  });
}

/**
 * The text of `root` that is shown with less than `least` contrast against what lies
 * behind it, its opacity counted: [{ text, ratio }].
 */
function lowContrast(page, root, least = 4.5) {
  return page.evaluate(([selector, least]) => {
    const rgb = (text) => text.match(/[\d.]+/g).map(Number);
    const luminance = ([r, g, b]) => {
      const c = [r, g, b].map((v) => v / 255).map((v) => (v <= 0.03928 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4));
      return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    };
    const background = (el) => {
      for (let at = el; at; at = at.parentElement) {
        const colour = rgb(getComputedStyle(at).backgroundColor);
        if (colour.length < 4 || colour[3] > 0) return colour.slice(0, 3);
      }
      return [255, 255, 255];
    };
    const opacity = (el) => {
      let product = 1;
      for (let at = el; at; at = at.parentElement) product *= Number(getComputedStyle(at).opacity);
      return product;
    };
    const found = [];
    for (const el of document.querySelector(selector).querySelectorAll('*')) {
      const own = [...el.childNodes].some((node) => node.nodeType === Node.TEXT_NODE && node.textContent.trim());
      if (!own || !el.getClientRects().length || el.closest('[hidden]') || el.closest('.plot-summary')) continue;
      if (el.disabled) continue;
      const back = background(el);
      const alpha = opacity(el);
      const fore = rgb(getComputedStyle(el).color).slice(0, 3).map((v, i) => alpha * v + (1 - alpha) * back[i]);
      const [a, b] = [luminance(fore), luminance(back)].sort((x, y) => y - x);
      const ratio = (a + 0.05) / (b + 0.05);
      if (ratio < least) found.push({ text: el.textContent.trim().slice(0, 40), ratio: Math.round(ratio * 100) / 100 });
    }
    return found;
  }, [root, least]);
}

for (const [size, viewport] of sizes) {
  test(`a stale run's plots at the ${size}'s size: dimmed drawings, legible text, a badge saying so`, bounded, async () => {
    const page = await openPage(browser, `${server.url}/ekf`, viewport);
    await page.locator('#r-x').fill('-1');
    await page.waitForFunction(() => document.getElementById('ekf-plots').classList.contains('stale'));
    const stale = await page.evaluate(() => {
      const figure = document.querySelector('#ekf-plots figure.plot');
      return {
        chart: Number(getComputedStyle(figure.querySelector(':scope > .stack, :scope > .chart')).opacity),
        badge: getComputedStyle(figure, '::after').content,
      };
    });
    assert.deepEqual(await lowContrast(page, '#ekf-plots'), []);
    assert.ok(stale.chart < 1, `the drawing is dimmed: ${stale.chart}`);
    assert.match(stale.badge, /stale/);
    const odometry = await openPage(browser, `${server.url}/odometry`, viewport);
    await odometry.locator('#size').fill('0');
    await odometry.waitForFunction(() => document.getElementById('belief-view').classList.contains('stale'));
    assert.deepEqual(await lowContrast(odometry, '#belief-view'), []);
    assert.deepEqual([...page.problems, ...odometry.problems], []);
    await odometry.close();
    await page.close();
  });
}

/** The page's headings that skip a level going down, and its table headers without text. */
function structure(page) {
  return page.evaluate(() => {
    const headings = [...document.querySelectorAll('h1, h2, h3, h4, h5, h6')].filter((h) => h.getClientRects().length);
    const skips = [];
    headings.forEach((h, i) => {
      const level = Number(h.tagName[1]);
      const before = i ? Number(headings[i - 1].tagName[1]) : 0;
      if (level > before + 1) skips.push(`${h.tagName} "${h.textContent.slice(0, 40)}" after h${before}`);
    });
    const empty = [...document.querySelectorAll('th')].filter((th) => !th.textContent.trim()).map((th) => th.closest('table').id || th.closest('table').className);
    return { skips, empty };
  });
}

test('the result panels: no skipped heading level, no empty table header; the read-only editor is named and reached', bounded, async () => {
  const correct = readFileSync(join(root, 'tests', 'student', 'correct.js'), 'utf8');
  // A classic mistake: failing cases with their differing elements in a table.
  const mistaken = correct.replace(/function predict\(([^)]*)\) \{/, 'function predict($1) { R = R.map((row) => row.map((v) => 2 * v));');
  assert.notEqual(mistaken, correct);
  const page = await openPage(browser, `${server.url}/ekf/code`, phone);
  await typeInEditor(page, mistaken);
  await runAndWait(page, '#run-tests');
  await page.locator('#test-predict table.mismatches').first().waitFor();
  assert.deepEqual(await structure(page), { skips: [], empty: [] });
  assert.deepEqual(page.problems, []);
  await page.close();
  // A submission opened read-only (a server with a course shows its student the code):
  // its editor has a name and takes the keyboard, and its result panel is as well formed.
  const course = await startServer();
  try {
    const { students: [pupil] } = setUpCourse(course, { title: 'Rough edges', prefix: 're', count: 1, role: 'assistant' });
    const cookie = await signIn(course, pupil.code);
    const response = await fetch(`${course.url}/api/submissions`, {
      method: 'POST',
      headers: { 'content-type': 'application/json', cookie },
      body: JSON.stringify({ source: mistaken, lab: 'ekf-localization' }),
    });
    assert.ok(response.ok, await response.clone().text());
    const { id } = await response.json();
    const context = await browser.newContext({ viewport: laptop });
    const [name, value] = cookie.split('=');
    await context.addCookies([{ name, value, url: course.url }]);
    const viewer = await openPage(context, `${course.url}/ekf/code?submission=${id}`);
    await viewer.waitForSelector('#viewer-result[data-status=graded]', { timeout: 120_000 });
    const content = viewer.locator('#viewer-source .cm-content');
    assert.equal(await content.getAttribute('aria-label'), 'the code submitted, read-only');
    await content.focus();
    assert.ok(await content.evaluate((el) => document.activeElement === el), 'the read-only editor takes the focus');
    await viewer.locator('#viewer-result details.server-tests').evaluate((el) => { el.open = true; });
    assert.deepEqual(await structure(viewer), { skips: [], empty: [] });
    assert.deepEqual(viewer.problems, []);
    await context.close();
  } finally {
    await course.stop();
  }
});
