// `wave view` in a real browser (Debian's Chromium driven by playwright-core): every
// output form of the default scene is loaded by the page (three.js GLTFLoader +
// DRACOLoader, served locally), its reported vertex and frame counts are checked
// against the run's report, frames are stepped and compared with the uncompressed
// files form vertex by vertex (exactly for plain, within the quantisation step for
// KHR_mesh_quantization and Draco), the attribute colouring is exercised, and a
// screenshot must show a lit, coloured surface.
//   node test_viewer.mjs WAVE_BINARY VIEWER_NODE_MODULES WORK_DIR
// Exit 77 (skipped) when Chromium is not installed.
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import assert from 'node:assert/strict';

const [wave, modules, work] = process.argv.slice(2);
const CHROMIUM = '/usr/bin/chromium';
if (!fs.existsSync(CHROMIUM)) {
  console.log('SKIP: /usr/bin/chromium is not installed (Debian package chromium)');
  process.exit(77);
}
const { chromium } = await import(pathToFileURL(path.resolve(modules, 'playwright-core', 'index.mjs')).href);

const FRAMES = 6;
fs.rmSync(work, { recursive: true, force: true });
fs.mkdirSync(work, { recursive: true });

function run(args, expectCode = 0) {
  const r = spawnSync(wave, args, { encoding: 'utf8' });
  assert.equal(r.status, expectCode, `wave ${args.join(' ')}: exit ${r.status}\n${r.stderr}`);
  return r;
}

// The outputs: every form, plain / quantised / Draco, glb and gltf containers.
const forms = {
  files: ['--form', 'files', '--codec', 'none'],
  'files-draco': ['--form', 'files', '--draco'],
  morph: ['--form', 'morph', '--codec', 'none'],
  'morph-quantized': ['--form', 'morph', '--quantize'],
  'morph-draco-gltf': ['--form', 'morph', '--draco', '--container', 'gltf'],
  nodes: ['--form', 'nodes', '--codec', 'none'],
  'nodes-draco': ['--form', 'nodes', '--draco'],
  'nodes-quantized': ['--form', 'nodes', '--quantize'],
  'files-meshopt': ['--form', 'files', '--codec', 'meshopt'],
  'morph-meshopt': ['--form', 'morph', '--codec', 'meshopt'],
};
// The default bay without its far field, so that every form holds the plain files form's
// mesh in its order (the far field's skirt, a second primitive of Draco and quantised
// frames, is checked below).
const bay = path.join(work, 'bay.json');
fs.writeFileSync(bay, JSON.stringify({
  name: 'viewer test: the default bay', seafloor: { source: 'gonzato-bay' },
  waves: [{ period: 5, amplitude: 0.3, direction: [0, 1] }], trace: { ray_spacing: 1 },
  fronts: { step: 0.4, split_distance: 1.2 }, surface: { far_field: false },
}));
const reports = {};
for (const [name, args] of Object.entries(forms)) {
  run(['run', bay, '--frames', `0:${FRAMES}`, '-q', '-o', path.join(work, name), ...args]);
  reports[name] = JSON.parse(fs.readFileSync(path.join(work, name, `report-frames-0-${FRAMES}.json`), 'utf8'));
}

// Bad input: exit 2 with the path named, before any server starts.
{
  const r = run(['view', path.join(work, 'nowhere')], 2);
  assert.match(r.stderr, /no such file or folder '.*nowhere'/);
  fs.mkdirSync(path.join(work, 'empty'));
  assert.match(run(['view', path.join(work, 'empty')], 2).stderr, /no libwave output in/);
  assert.match(run(['view', path.join(work, 'files', 'strips.ply')], 2).stderr, /not a libwave output/);
}

// Starts `wave ARGS` (a view); resolves with the URL it prints (with this run's token),
// its base and a fetch of a path that carries the token.
function serve(dir, args = ['view', dir, '--port', '0', '--no-open'], env = process.env) {
  const child = spawn(wave, args, { stdio: ['ignore', 'pipe', 'pipe'], env });
  return new Promise((resolve, reject) => {
    let out = '';
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/(http:\/\/127\.0\.0\.1:\d+\/)\?token=([0-9a-f]{32})/);
      if (m) {
        const get = (p, init) => fetch(m[1] + p + (p.includes('?') ? '&' : '?') + 'token=' + m[2], init);
        resolve({ url: m[0], base: m[1], token: m[2], get, child });
      }
    });
    child.on('exit', (code) => reject(new Error(`wave view exited ${code}: ${out}`)));
  });
}

// `wave run --view` without a display prints the URL and serves the new output; the
// server answers only inside its folders.
{
  const env = { ...process.env };
  delete env.DISPLAY;
  delete env.WAYLAND_DISPLAY;
  const out = path.join(work, 'viewed');
  const { url, base, get, child } = await serve(out, ['run', '--frames', '0:2', '-q', '-o', out, '--view'], env);
  const list = await (await get('api/outputs')).json();
  assert.deepEqual(list.outputs.map((o) => o.name), ['animation-frames-0-2.glb']);
  assert.match(await (await get('')).text(), /<title>wave view<\/title>/);
  const glb = await (await get('out/animation-frames-0-2.glb')).arrayBuffer();
  assert.equal(glb.byteLength, fs.statSync(path.join(out, 'animation-frames-0-2.glb')).size);
  // Only inside the folder: traversals in every encoding, and links leaving it, are 404;
  // a link that stays inside is served.
  fs.symlinkSync('/etc', path.join(out, 'etcdir'));
  fs.symlinkSync('/etc/passwd', path.join(out, 'passwd.glb'));
  fs.symlinkSync('animation-frames-0-2.glb', path.join(out, 'inside.glb'));
  for (const escape of ['out/../report-frames-0-2.json', 'out/%2e%2e/%2e%2e/etc/passwd', 'out/..%2f..%2fetc%2fpasswd',
    'out/%2E%2e/report-frames-0-2.json', 'out/.%2E/.%2e/etc/passwd', 'out/%2f%2e%2e%2fetc/passwd', '../etc/passwd',
    'out/etcdir/passwd', 'out/passwd.glb', 'out/', 'out/nonexistent.glb'])
    assert.equal((await get(escape)).status, 404, `${escape} must not be served`);
  assert.equal((await get('out/inside.glb')).status, 200);
  // Without the token, or from a page of another site (DNS rebinding: its own Host), or
  // with another method: refused.
  assert.equal((await fetch(base + 'out/animation-frames-0-2.glb')).status, 403);
  assert.equal((await fetch(base + 'out/animation-frames-0-2.glb?token=' + '0'.repeat(32))).status, 403);
  const withHost = (host) => new Promise((resolve, reject) => {  // fetch() cannot set Host; node's http can
    const u = new URL(url);
    http.get({ host: '127.0.0.1', port: u.port, path: '/out/animation-frames-0-2.glb' + u.search, headers: { Host: host } },
      (res) => { res.resume(); resolve(res.statusCode); }).on('error', reject);
  });
  assert.equal(await withHost('attacker.example:' + new URL(url).port), 403);
  assert.equal(await withHost('127.0.0.1.attacker.example:' + new URL(url).port), 403);
  assert.equal(await withHost('localhost:' + new URL(url).port), 200);
  assert.equal((await get('out/animation-frames-0-2.glb', { method: 'POST' })).status, 405);
  const head = await get('out/animation-frames-0-2.glb', { method: 'HEAD' });
  assert.equal(head.status, 200);
  assert.equal(head.headers.get('x-content-type-options'), 'nosniff');
  assert.equal(head.headers.get('access-control-allow-origin'), null);
  // A port in use is an error when asked for, naming it.
  const port = new URL(url).port;
  const busy = spawnSync(wave, ['view', out, '--port', port, '--no-open'], { encoding: 'utf8' });
  assert.equal(busy.status, 2);
  assert.match(busy.stderr, new RegExp(`port ${port} on 127.0.0.1 is in use`));
  child.kill('SIGTERM');
  // With a display the URL goes to the desktop's browser (xdg-open).
  const bin = path.join(work, 'bin');
  fs.mkdirSync(bin, { recursive: true });
  // Written aside and renamed: the file appears only whole (a redirect creates it empty first).
  fs.writeFileSync(path.join(bin, 'xdg-open'),
    `#!/bin/sh\necho "$1" > ${path.join(work, 'opened.tmp')}\nmv ${path.join(work, 'opened.tmp')} ${path.join(work, 'opened.txt')}\n`, { mode: 0o755 });
  const shown = await serve(out, ['view', out, '--port', '0'], { ...env, DISPLAY: ':99', PATH: `${bin}:${process.env.PATH}` });
  for (let i = 0; i < 50 && !fs.existsSync(path.join(work, 'opened.txt')); ++i) await new Promise((r) => setTimeout(r, 100));
  assert.equal(fs.readFileSync(path.join(work, 'opened.txt'), 'utf8').trim(), shown.url);
  shown.child.kill('SIGTERM');
  console.log('ok   wave run --view, the URL, xdg-open with a display, a busy port, no escape from the folders');
}

const browser = await chromium.launch({
  executablePath: CHROMIUM,
  headless: true,
  // The machine's closed network: no background connections; WebGL by SwiftShader.
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const page = await browser.newPage({ viewport: { width: 960, height: 600 } });
const external = [];
page.on('request', (req) => {
  const u = req.url();  // blob: and data: are the page's own (the Draco worker, the screenshot check)
  if (!u.startsWith('http://127.0.0.1:') && !u.startsWith('data:') && !u.startsWith('blob:http://127.0.0.1:')) external.push(u);
});
page.on('response', (res) => { if (res.status() >= 400) consoleErrors.push(`HTTP ${res.status()} for ${res.url()}`); });
const consoleErrors = [];
page.on('console', (msg) => { if (msg.type() === 'error' && !msg.text().startsWith('Failed to load resource')) consoleErrors.push(msg.text()); });
page.on('pageerror', (e) => consoleErrors.push(String(e)));

async function open(name) {
  const server = await serve(path.join(work, name));
  await page.goto(server.url);
  const info = await page.evaluate(() => window.wave.ready);
  return { server, info };
}

// Largest per-axis distance between two frames' positions.
function maxDiff(a, b) {
  assert.equal(a.length, b.length);
  let d = 0;
  for (let i = 0; i < a.length; ++i) d = Math.max(d, Math.abs(a[i] - b[i]));
  return d;
}

// Draco's edgebreaker reorders points: every decoded point must lie within `tol`
// (per axis) of a reference point, and the counts must agree.
function matchPoints(decoded, reference, tol, sameCount = true) {
  if (sameCount) assert.equal(decoded.length, reference.length, 'vertex counts');
  const cell = 4 * tol, grid = new Map();
  const key = (x, y, z) => `${Math.floor(x / cell)},${Math.floor(y / cell)},${Math.floor(z / cell)}`;
  for (let i = 0; i < reference.length; i += 3) {
    const k = key(reference[i], reference[i + 1], reference[i + 2]);
    if (!grid.has(k)) grid.set(k, []);
    grid.get(k).push(i);
  }
  let worst = 0;
  for (let i = 0; i < decoded.length; i += 3) {
    const [x, y, z] = [decoded[i], decoded[i + 1], decoded[i + 2]];
    let best = Infinity;
    for (let dx = -1; dx <= 1; ++dx) for (let dy = -1; dy <= 1; ++dy) for (let dz = -1; dz <= 1; ++dz) {
      const list = grid.get(`${Math.floor(x / cell) + dx},${Math.floor(y / cell) + dy},${Math.floor(z / cell) + dz}`) || [];
      for (const j of list) best = Math.min(best, Math.max(Math.abs(reference[j] - x), Math.abs(reference[j + 1] - y), Math.abs(reference[j + 2] - z)));
    }
    worst = Math.max(worst, best);
  }
  assert.ok(worst <= tol, `a decoded point is ${worst} from every reference point (tolerance ${tol})`);
  return worst;
}

// A screenshot's PNG decoded in the page; `reduce(rgba, width, height)` runs there too
// and its (small) result comes back.
async function inPage(png, reduce) {
  return inPageAll([png], `(images) => (${reduce.toString()})(images[0].data, images[0].width, images[0].height)`);
}

// Several screenshots' ImageData decoded in the page; `reduce(images)` (a function, or
// its source) runs there too.
async function inPageAll(pngs, reduce) {
  return page.evaluate(`(async (list) => {
    const images = [];
    for (const b64 of list) {
      const img = new Image();
      img.src = 'data:image/png;base64,' + b64;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width; c.height = img.height;
      const ctx = c.getContext('2d');
      ctx.drawImage(img, 0, 0);
      images.push(ctx.getImageData(0, 0, c.width, c.height));
    }
    return (${typeof reduce === 'string' ? reduce : reduce.toString()})(images);
  })(${JSON.stringify(pngs.map((p) => p.toString('base64')))})`);
}

function range(positions) {
  let r = 0;
  for (let c = 0; c < 3; ++c) {
    let lo = Infinity, hi = -Infinity;
    for (let i = c; i < positions.length; i += 3) { lo = Math.min(lo, positions[i]); hi = Math.max(hi, positions[i]); }
    r = Math.max(r, hi - lo);
  }
  return r;
}

// Reference: the plain files form, frame by frame.
const reference = [];
const referenceFoam = [];
let failures = 0;
const check = async (label, fn) => {
  try {
    await fn();
    console.log(`ok   ${label}`);
  } catch (e) {
    ++failures;
    console.log(`FAIL ${label}: ${e.message}`);
  }
};

for (const name of Object.keys(forms)) {
  const { server, info } = await open(name);
  await check(`${name}: counts`, async () => {
    const expected = name.split('-')[0];
    assert.equal(info.form, expected);
    assert.equal(info.compression, name.includes('draco') ? 'Draco' : name.includes('quantized') ? 'quantised'
      : name.includes('meshopt') ? 'meshopt' : 'plain');
    assert.equal(info.frames, FRAMES);
    assert.equal(info.vertices, reports[name].surface.vertices);
    assert.equal(info.triangles, reports[name].surface.triangles);
    assert.equal(info.fps, reports[name].surface.fps);
  });
  await check(`${name}: frames step and match the plain files form`, async () => {
    const frames = [];
    for (const f of [0, 3, FRAMES - 1]) {
      assert.equal(await page.evaluate((k) => window.wave.setFrame(k), f), f);
      frames[f] = await page.evaluate(() => window.wave.positions());
    }
    assert.ok(maxDiff(frames[0], frames[3]) > 0.01, 'the geometry changes between frames 0 and 3');
    if (name === 'files') {
      for (const f of [0, 3, FRAMES - 1]) reference[f] = frames[f];
      return;
    }
    const span = range(reference[0]);
    for (const f of [0, 3, FRAMES - 1]) {
      if (name.includes('draco') && name !== 'morph-draco-gltf') {
        // 14-bit positions over the largest extent: one quantisation step.
        matchPoints(frames[f], reference[f], span / ((1 << 14) - 1) * 1.01);
      } else {
        // Plain: float sums only; quantised: int16 steps of the morph/position range
        // (the morph form's Draco base is decoded in order, 14 bits).
        // meshopt: the exponential filter's steps (docs/export.md: heights 2^-17 m,
        // horizontal 1/512 of the shortest edge), far under a millimetre on the bay.
        const tol = name === 'morph' || name === 'nodes' ? 1e-4 : name.includes('meshopt') ? 1e-3
          : name === 'morph-draco-gltf' ? span / ((1 << 14) - 1) * 1.01 : span / 32767 * 2.02;
        const d = maxDiff(frames[f], reference[f]);
        assert.ok(d <= tol, `frame ${f}: ${d} m from the plain files form (tolerance ${tol})`);
      }
    }
  });
  await check(`${name}: attributes`, async () => {
    await page.evaluate(() => window.wave.setFrame(3));
    const foam = await page.evaluate(() => window.wave.values('foam'));
    const reflect = await page.evaluate(() => window.wave.values('reflect'));
    const refract = await page.evaluate(() => window.wave.values('refract'));
    assert.equal(foam.length, info.vertices);
    for (let i = 0; i < reflect.length; ++i) {
      assert.ok(foam[i] >= -1e-3 && foam[i] <= 1 + 1e-3, `foam ${foam[i]}`);
      assert.ok(Math.abs(reflect[i] + refract[i] - 1) < 2e-3, `R + T = ${reflect[i] + refract[i]}`);
    }
    if (name === 'files') referenceFoam.push(...foam);
    else if (!name.includes('draco')) assert.ok(maxDiff(foam, referenceFoam) < 1e-3, 'foam as in the plain files form');
    const water = await page.evaluate(async () => { await window.wave.setColor('water'); return window.wave.colors(); });
    const byFoam = await page.evaluate(async () => { await window.wave.setColor('foam'); return window.wave.colors(); });
    assert.ok(maxDiff(water, byFoam) > 0.05, 'the colour selector changes the colours');
    await page.evaluate(() => window.wave.setColor('water'));
  });
  if (name === 'nodes-draco' || name === 'morph') {
    await check(`${name}: plays at the file's fps and loops`, async () => {
      await page.evaluate(() => window.wave.setFrame(0));
      await page.evaluate(() => window.wave.play());
      await page.waitForFunction(() => window.wave.frame >= 2, null, { timeout: 10000 });
      await page.evaluate(() => window.wave.pause());
    });
    await check(`${name}: draws only when something changes`, async () => {
      await page.evaluate(() => window.wave.setFrame(1));
      await page.waitForTimeout(200);  // the frame's draw
      const idle = await page.evaluate(() => window.wave.draws);
      await page.waitForTimeout(500);
      assert.equal(await page.evaluate(() => window.wave.draws), idle, 'a paused page draws again and again');
      await page.evaluate(() => window.wave.setFrame(2));
      await page.waitForFunction((n) => window.wave.draws > n, idle, { timeout: 5000 });
    });
    await check(`${name}: screenshot shows the surface`, async () => {
      await page.evaluate(() => window.wave.setFrame(2));
      await page.waitForTimeout(300);
      const file = path.join(work, `${name}.png`);
      await page.screenshot({ path: file });
      const stats = await inPage(fs.readFileSync(file), (d) => {
        const bg = [d[0], d[1], d[2]];  // the top-left corner: background
        let differs = 0;
        const colours = new Set();
        for (let i = 0; i < d.length; i += 4) {
          if (Math.abs(d[i] - bg[0]) + Math.abs(d[i + 1] - bg[1]) + Math.abs(d[i + 2] - bg[2]) > 30) ++differs;
          colours.add((d[i] >> 3) << 10 | (d[i + 1] >> 3) << 5 | (d[i + 2] >> 3));
        }
        return { share: differs / (d.length / 4), colours: colours.size };
      });
      assert.ok(stats.share > 0.15, `only ${(100 * stats.share).toFixed(1)} % of the screenshot differs from the background`);
      assert.ok(stats.colours > 50, `only ${stats.colours} colours: a blank or flat image`);
    });
  }
  server.child.kill('SIGTERM');
}

// The default scene as a user runs it (its quantised morph file, with the far field)
// and as meshopt files must draw as its plain float run does: the page fits the same
// camera to the domain, so the screenshots match pixel for pixel but for rounding. (The
// quantised morph file once clamped the skirt's TEXCOORD_0 into [0, 1]: the page framed
// 160 km of skirt and drew a white striped rectangle.)
{
  const outs = { plain: ['--codec', 'none'], quantized: [], meshopt: ['--form', 'files', '--codec', 'meshopt'] };
  const shots = {};
  for (const [name, args] of Object.entries(outs)) {
    run(['run', '--frames', '0:3', '-q', '-o', path.join(work, `default-${name}`), ...args]);
    const { server } = await open(`default-${name}`);
    await page.evaluate(() => window.wave.setFrame(2));
    await page.waitForTimeout(300);
    shots[name] = await page.screenshot();
    server.child.kill('SIGTERM');
  }
  for (const name of ['quantized', 'meshopt']) {
    await check(`the default scene, ${name}: draws as its plain float run`, async () => {
      const share = await inPageAll([shots[name], shots.plain], ([x, y]) => {
        let differ = 0, counted = 0;
        for (let row = 90; row < x.height - 90; ++row)  // not the info box nor the controls
          for (let col = 0; col < x.width; ++col) {
            const i = 4 * (row * x.width + col);
            ++counted;
            if (Math.abs(x.data[i] - y.data[i]) + Math.abs(x.data[i + 1] - y.data[i + 1]) + Math.abs(x.data[i + 2] - y.data[i + 2]) > 40) ++differ;
          }
        return differ / counted;
      });
      assert.ok(share < 0.02, `${(100 * share).toFixed(1)} % of the pixels differ from the plain run's screenshot`);
    });
  }
}

// The default bay with its far field as Draco files: the skirt is a second primitive
// (docs/far-field.md), which the page joins into one mesh of the run's vertices; the
// domain within half its lattice's step of the plain files form (2^-8 m: 14 bits over
// 100 m, in quarter metres so that Draco's six printed decimals keep it; the node's
// scale undoes them), the skirt within half of its own (2^-5 m: 80 km each way in fewer
// than 2^23 steps). Quantised nodes: the
// skirt's floats in the int16 node frame, joined likewise; the bay within half an int16
// step (1.53 mm over its 100 m), the skirt within float32's reach at 80 km (1 cm).
{
  const far = {};
  for (const [name, args] of [['far-files', ['--form', 'files', '--codec', 'none']], ['far-files-draco', ['--form', 'files', '--draco']],
    ['far-nodes-quantized', ['--form', 'nodes', '--quantize']]]) {
    run(['run', '--frames', '0:3', '-q', '-o', path.join(work, name), ...args]);
    const report = JSON.parse(fs.readFileSync(path.join(work, name, 'report-frames-0-3.json'), 'utf8'));
    const { server, info } = await open(name);
    await page.evaluate(() => window.wave.setFrame(2));
    far[name] = { report, info, positions: await page.evaluate(() => window.wave.positions()) };
    server.child.kill('SIGTERM');
  }
  await check('Draco files with the far field: one mesh of the run\'s vertices, on the lattices', async () => {
    const [plain, draco] = [far['far-files'], far['far-files-draco']];
    assert.ok(draco.report.surface.far_field, 'the Draco run keeps the far field');
    assert.equal(draco.info.vertices, plain.report.surface.vertices);
    assert.equal(draco.info.triangles, plain.report.surface.triangles);
    matchPoints(draco.positions, plain.positions, 2 ** -6 * 1.01);
    const inside = [];  // glTF axes: the bay's x in [0, 100], z = −y in [−90, 0]; off its border
    for (let i = 0; i < draco.positions.length; i += 3) {
      const [x, , z] = draco.positions.slice(i, i + 3);
      if (x > 1 && x < 99 && z > -89 && z < -1) inside.push(...draco.positions.slice(i, i + 3));
    }
    assert.ok(inside.length > 3 * 5000, `${inside.length / 3} vertices inside the bay`);
    matchPoints(inside, plain.positions, 2 ** -9 * 1.01, false);
  });
  await check('quantised nodes with the far field: one mesh of the run\'s vertices, the bay on its int16 grid', async () => {
    const [plain, quantised] = [far['far-files'], far['far-nodes-quantized']];
    assert.ok(quantised.report.surface.far_field, 'the quantised run keeps the far field');
    assert.equal(quantised.info.vertices, plain.report.surface.vertices);
    assert.equal(quantised.info.triangles, plain.report.surface.triangles);
    matchPoints(quantised.positions, plain.positions, 1e-2);
    const inside = [];
    for (let i = 0; i < quantised.positions.length; i += 3) {
      const [x, , z] = quantised.positions.slice(i, i + 3);
      if (x >= 0 && x <= 100 && z >= -90 && z <= 0) inside.push(...quantised.positions.slice(i, i + 3));
    }
    assert.ok(inside.length > 3 * 5000, `${inside.length / 3} vertices inside the bay`);
    matchPoints(inside, plain.positions, 100 / 65534 / 2 + 2e-5, false);
  });
  // Haze on the seafloor (Koschmieder's law, as in the Blender add-on): from 400 m above
  // the bay looking inland, the apron's land runs to the horizon 80 km out. Without haze
  // it meets the background on a hard line; with the default 40 km visibility the rows
  // just below the horizon (tens of km away) are mostly background, while the near land
  // (the lowest rows, 1–2 km away: ~15 % haze) keeps most of its colour.
  await check('haze: the far land fades into the background, the near land does not; the seafloor on every frame', async () => {
    const { server } = await open('far-files');
    await page.evaluate(() => window.wave.setFrame(0));  // the files form's frame 0 carries the seafloor
    await page.evaluate(() => window.wave.sky(false));  // measured against the flat background behind the sky
    const shot = async (visibility) => {
      await page.evaluate((v) => { window.wave.look([50, 400, 300], [50, 0, -6000]); window.wave.haze(v); }, visibility);
      await page.waitForTimeout(300);
      // Per row, the mean |colour − background| over the right half (clear of the info panel).
      return inPage(await page.screenshot(), (d, width, height) => {
        const at = (x, y) => 4 * (y * width + x), x0 = Math.floor(width / 2), x1 = width - 10;
        const bg = d.slice(at(x1, 5), at(x1, 5) + 3);
        const rows = [];
        for (let y = 0; y < height; ++y) {
          let sum = 0;
          for (let x = x0; x < x1; ++x) for (let k = 0; k < 3; ++k) sum += Math.abs(d[at(x, y) + k] - bg[k]);
          rows.push(sum / (x1 - x0));
        }
        return rows;
      });
    };
    const clear = await shot(0), hazy = await shot(40000);
    assert.equal(await page.evaluate(() => window.wave.haze()), 40000);
    // The bar's "haze (km)" field sets the same visibility.
    await page.fill('#haze', '12');
    await page.dispatchEvent('#haze', 'change');
    assert.equal(await page.evaluate(() => window.wave.haze()), 12000);
    await page.evaluate(() => window.wave.haze(40000));
    // The files form's later frames carry the water only: the page keeps frame 0's
    // seafloor on show (this view holds land only, so frame 2 looks as frame 0 does).
    await page.evaluate(() => window.wave.setFrame(2));
    const later = await shot(40000);
    await page.evaluate(() => window.wave.sky(true));
    server.child.kill('SIGTERM');
    const gap = Math.max(...later.map((v, y) => Math.abs(v - hazy[y])));
    assert.ok(gap < 3, `frame 2 differs from frame 0 by ${gap} per row: the seafloor is not shown`);
    const horizon = clear.findIndex((v) => v > 30);
    assert.ok(horizon > 0 && horizon < 0.6 * clear.length, `the land's horizon at row ${horizon}`);
    const mean = (rows, from, to) => rows.slice(from, to).reduce((a, b) => a + b, 0) / (to - from);
    const far = [mean(clear, horizon, horizon + 8), mean(hazy, horizon, horizon + 8)];
    const nearRow = Math.floor(0.82 * clear.length);  // above the control bar
    const near = [mean(clear, nearRow - 8, nearRow), mean(hazy, nearRow - 8, nearRow)];
    console.log(`     haze: far land ${far[0].toFixed(1)} → ${far[1].toFixed(1)}, near land ${near[0].toFixed(1)} → ${near[1].toFixed(1)} from the background`);
    assert.ok(far[1] < 0.5 * far[0], `the far land is not hazed: ${far[0]} → ${far[1]}`);
    assert.ok(near[1] > 0.8 * near[0], `the near land is hazed too: ${near[0]} → ${near[1]}`);
  });
}

// The sky (issue 66): three's Sky with its sun where the file's sun lamp points (the
// lamp shines along its −Z: the sun lies along its +Z), drawn above the horizon.
await check('sky: its sun is the file\'s sun lamp, and it is drawn above the horizon', async () => {
  const { server } = await open('morph');
  const doc = (() => {
    const glb = fs.readFileSync(path.join(work, 'morph', `animation-frames-0-${FRAMES}.glb`));
    return JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString('utf8'));
  })();
  const lampNode = doc.nodes.find((n) => n.extensions && n.extensions.KHR_lights_punctual);
  const [x, y, z, w] = lampNode.rotation || [0, 0, 0, 1];
  // The quaternion's image of +Z.
  const want = [2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)];
  const sky = await page.evaluate(() => window.wave.sky());
  assert.ok(sky.shown);
  for (let k = 0; k < 3; ++k) assert.ok(Math.abs(sky.sun[k] - want[k]) < 1e-6, `sky sun ${sky.sun} vs the lamp's +Z ${want}`);
  // Level with the water, looking out to sea: the upper rows are sky — bluish, and not
  // the flat background — and with the sky hidden they are the background.
  const upper = async () => {
    await page.evaluate(() => window.wave.look([50, 3, 20], [50, 3, 2000]));
    await page.waitForTimeout(300);
    return inPage(await page.screenshot(), (d, width) => {
      let r = 0, g = 0, b = 0, n = 0;
      for (let row = 100; row < 140; ++row) for (let col = width / 2; col < width - 10; ++col) {
        const i = 4 * (row * width + col);
        r += d[i]; g += d[i + 1]; b += d[i + 2]; ++n;
      }
      return [r / n, g / n, b / n];
    });
  };
  const withSky = await upper();
  await page.evaluate(() => window.wave.sky(false));
  const flat = await upper();
  await page.evaluate(() => window.wave.sky(true));
  server.child.kill('SIGTERM');
  console.log(`     sky: upper rows ${withSky.map((v) => v.toFixed(0))}, flat background ${flat.map((v) => v.toFixed(0))}`);
  assert.ok(withSky[2] > withSky[0] + 10, `the sky is not blue: ${withSky}`);
  assert.ok(Math.abs(withSky[0] - flat[0]) + Math.abs(withSky[1] - flat[1]) + Math.abs(withSky[2] - flat[2]) > 20, 'no sky drawn');
});

await check('nothing was fetched from outside 127.0.0.1', async () => assert.deepEqual(external, []));
await check('no errors in the page', async () => assert.deepEqual(consoleErrors, []));
await browser.close();
if (failures) {
  console.log(`${failures} check(s) failed`);
  process.exit(1);
}
console.log('all viewer checks passed');
