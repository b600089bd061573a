// A load test of psh view's server on loopback (bounded: a fixed number of requests,
// each with a timeout): frame rates of one client orbiting the camera and turning the
// environment (frame, encode and transfer times apart), then many clients at once, bad
// requests and clients that leave mid-frame. Asserts correctness and bounds only, never a
// time: every frame answer is 200 or 503 (busy), bad parameters 400, unknown paths 404,
// the server answers after it all, and its resident memory stays under a bound: what it
// held after start-up, plus 1 GiB per band-limit setting (the transfer sampled over turns,
// pprt::stages::TransferTurns::MAX_BYTES), plus 512 MiB for the frames in flight.
//
//   node view/tests/load.mjs [WxH [SCENE]]   (default 512x384, the built-in scene; a scene
//                                            file renders at its camera's size)
import { mkdtempSync, rmSync } from "node:fs";
import os from "node:os";
import path from "node:path";
import { startView, stopView, rssMiB } from "./server.mjs";

const size = process.argv[2] || "512x384", scene = process.argv[3];
const CLIENTS = 8, PER_CLIENT = 6;
let passed = 0, failed = 0;
function check(name, ok, detail) {
  console.log(`${ok ? "ok" : "FAILED"}: ${name}${detail ? ` (${detail})` : ""}`);
  if (ok) passed++; else failed++;
}

const saves = mkdtempSync(path.join(os.tmpdir(), "psh-view-load-"));
const { url, child } = await startView([...(scene ? ["--scene", scene] : ["--size", size]), "--save-dir", saves]);
const { width: W, height: H } = await (await fetch(`${url}info`)).json();
const frameUrl = (p) => `${url}frame?` + new URLSearchParams({
  az: 0, el: 0, zoom: 1, turn: 0, w: W, h: H, bands: 0, show: "s0", valid: "project", preview: 0, ...p });
// One request with a timeout (no hang): status, bytes, server timings and milliseconds.
async function get(u, init = {}) {
  const t0 = performance.now();
  const r = await fetch(u, { signal: AbortSignal.timeout(120_000), ...init });
  const body = new Uint8Array(await r.arrayBuffer());
  const timing = Object.fromEntries([...(r.headers.get("server-timing") || "").matchAll(/(\w+);dur=([0-9.]+)/g)].map((m) => [m[1], Number(m[2])]));
  return { status: r.status, bytes: body.length, timing, ms: performance.now() - t0, body };
}
let peak = rssMiB(child.pid);
const sample = () => { peak = Math.max(peak, rssMiB(child.pid)); };
const rssStart = peak;

try {
  // One client: `n` frames, each changing the camera (or the environment), sequentially
  // as the page asks them; the mean of each stage and the frames per second.
  async function rate(name, n, params) {
    await get(frameUrl(params(0)));
    const sums = { turn: 0, camera: 0, frame: 0, encode: 0, transfer: 0, total: 0 };
    let ok = true;
    for (let k = 1; k <= n; k++) {
      const r = await get(frameUrl(params(k)));
      ok &&= r.status === 200;
      const server = (r.timing.turn || 0) + (r.timing.camera || 0) + (r.timing.frame || 0) + (r.timing.encode || 0);
      for (const key of ["turn", "camera", "frame", "encode"]) sums[key] += r.timing[key] || 0;
      sums.transfer += r.ms - server;
      sums.total += r.ms;
      sample();
    }
    const m = (x) => (x / n).toFixed(1);
    console.log(`${name}: ${(1e3 * n / sums.total).toFixed(1)} frames/s; per frame: environment turn ${m(sums.turn)} ms, camera ${m(sums.camera)} ms, frame ${m(sums.frame)} ms, encode ${m(sums.encode)} ms, transfer ${m(sums.transfer)} ms, total ${m(sums.total)} ms`);
    check(`${name}: every frame 200`, ok);
  }
  const half = { w: W >> 1, h: H >> 1, preview: 1 };
  await rate(`orbit, ${W} x ${H}`, 10, (k) => ({ az: 3 * k }));
  await rate(`orbit while dragging, ${half.w} x ${half.h}`, 10, (k) => ({ az: 3 * k, ...half }));
  const quarter = { w: W >> 2, h: H >> 2, preview: 1 };
  await rate(`orbit while dragging, ${quarter.w} x ${quarter.h}`, 10, (k) => ({ az: 3 * k, ...quarter }));
  // The first turn of a setting samples the transfer over turns (pprt::stages::TransferTurns):
  // the warm-up frame (k = 0) pays it.
  await rate(`environment turn, ${W} x ${H}`, 4, (k) => ({ turn: 5 * k + 1 }));
  await rate(`environment turn while dragging, ${half.w} x ${half.h}`, 4, (k) => ({ turn: 5 * k + 3, ...half }));
  const info = await (await fetch(`${url}info`)).json();
  if (info.bands.length > 1) {
    const [lo, hi] = info.bands[1];
    await rate(`environment turn while dragging, ${half.w} x ${half.h}, l_low ${lo}, l_high ${hi}`, 4, (k) => ({ turn: 5 * k + 1, bands: 1, ...half }));
  }
  await rate(`polarizer data, ${W} x ${H} (camera and environment still)`, 10, () => ({ show: "polarizer" }));

  // Many clients at once: each answer 200 or 503 (busy), never anything else or a hang.
  const t0 = performance.now();
  const statuses = await Promise.all(Array.from({ length: CLIENTS }, async (_, c) => {
    const got = [];
    for (let k = 0; k < PER_CLIENT; k++) {
      got.push((await get(frameUrl({ az: 7 * c + k, el: k, w: W >> 1, h: H >> 1, preview: 1 }))).status);
      sample();
    }
    return got;
  }));
  const all = statuses.flat();
  const count = (s) => all.filter((x) => x === s).length;
  console.log(`${CLIENTS} clients x ${PER_CLIENT} frames in ${((performance.now() - t0) / 1e3).toFixed(1)} s: ${count(200)} answered 200, ${count(503)} busy (503)`);
  check("concurrent clients: every answer 200 or 503", all.every((s) => s === 200 || s === 503), JSON.stringify(statuses));
  check("concurrent clients: some frames rendered", count(200) > 0);

  // Bad requests: 400 naming the parameter; no path reaches the file system.
  for (const [q, word] of [[{ az: "x" }, "az"], [{ w: 99999 }, "view size"], [{ show: "../etc/passwd" }, "show"],
    [{ bands: 7 }, "band limits"], [{ el: 120 }, "orbit"], [{ turn: "NaN" }, "turn"]]) {
    const r = await get(frameUrl(q));
    const text = new TextDecoder().decode(r.body);
    check(`bad ${Object.keys(q)[0]}=${Object.values(q)[0]}: 400 naming it`, r.status === 400 && text.includes(word), `${r.status} ${text.trim()}`);
  }
  for (const p of ["/../../etc/passwd", "/%2e%2e/Cargo.toml", "/scenes/buddha.toml", "/page.html"]) {
    const r = await get(url.replace(/\/$/, "") + p);
    check(`GET ${p}: 404`, r.status === 404, String(r.status));
  }
  const noPolarizers = await get(frameUrl({}).replace("/frame?", "/save?"), { method: "POST" });
  check("save without polarizers: 400", noPolarizers.status === 400, String(noPolarizers.status));

  // Clients that leave mid-frame (environment turns, the slowest frames): the server
  // stops their work and answers the next client.
  const before = await (await fetch(`${url}stats`)).json();
  for (let k = 0; k < 4; k++) {
    const controller = new AbortController();
    const pending = fetch(frameUrl({ turn: 90 + k }), { signal: controller.signal }).catch(() => null);
    await new Promise((r) => setTimeout(r, 30));
    controller.abort();
    await pending;
  }
  const after1 = await get(frameUrl({ az: 1 }));
  const after = await (await fetch(`${url}stats`)).json();
  const cancelled = after.cancelled - before.cancelled, rendered = after.rendered - before.rendered - 1;
  console.log(`left mid-frame: 4 clients; their frames stopped ${cancelled}, rendered to the end anyway ${rendered}`);
  check("the frames of clients that left were stopped", cancelled + rendered === 4 && cancelled >= 1, `${cancelled} stopped, ${rendered} rendered`);
  check("after clients left mid-frame, the next frame is 200", after1.status === 200, String(after1.status));
  sample();
  console.log(`server memory: ${rssStart.toFixed(0)} MiB after start-up, at most ${peak.toFixed(0)} MiB under load`);
  const bound = rssStart + 1024 * info.bands.length + 512;
  check(`server memory under ${bound.toFixed(0)} MiB`, peak < bound, `${peak.toFixed(0)} MiB`);
} finally {
  stopView(child);
  rmSync(saves, { recursive: true, force: true });
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
