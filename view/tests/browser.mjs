// psh view in a real browser (Debian's Chromium, headless, driven by playwright-core):
// load the page, drag the camera, turn the environment and the polarizer, and compare
// the pixels the page shows with the pictures `psh render` writes for the same camera,
// environment turn, band limits and picture (s0, AoLP, through the polarizer).
//
// Tolerance, per channel: 1/255 (one 8-bit step). The page's s0 and AoLP are computed by
// the same Rust code as psh render's PNGs, on a frame whose transfer was redone after the
// turn (retransfer, visibility kept) where psh render precomputes it whole: the two agree
// to rounding (1e-12 relative), which moves a value across an 8-bit step at most. The
// polarizer picture is computed by the page in JavaScript from f32 copies of s0..s2 (7
// significant digits), again within one step. Pixels whose PSH (70) flag (magenta) flips
// on such rounding would differ by more: at most 0.05% of the pixels may (reported).
//
//   node view/tests/browser.mjs        (after cargo build --release; $CHROMIUM or `which chromium`)
//   PSH_VIEW_SCENE=scenes/buddha.toml node view/tests/browser.mjs   (a scene file, its camera's size)
import { chromium } from "playwright-core";
import { execFileSync } from "node:child_process";
import { mkdirSync, mkdtempSync, readFileSync, rmSync } from "node:fs";
import os from "node:os";
import path from "node:path";
import { psh, root, startView, stopView } from "./server.mjs";

const scene = process.env.PSH_VIEW_SCENE;
const sceneArgs = scene ? ["--scene", scene] : ["--size", "256x192"];
const shots = path.join(root, "target/view-test", scene ? path.basename(scene, ".toml") : "builtin");
mkdirSync(shots, { recursive: true });
const tmp = mkdtempSync(path.join(os.tmpdir(), "psh-view-test-"));
const executablePath = process.env.CHROMIUM || execFileSync("which", ["chromium"]).toString().trim();

let passed = 0, failed = 0;
function check(name, ok, detail) {
  console.log(`${ok ? "ok" : "FAILED"}: ${name}${detail ? ` (${detail})` : ""}`);
  if (ok) passed++; else failed++;
}

const { url, child } = await startView([...sceneArgs, "--save-dir", path.join(tmp, "saves")]);
let browser;
try {
  // A fresh profile (--user-data-dir) in the temporary directory.
  browser = await chromium.launchPersistentContext(path.join(tmp, "chromium"), {
    executablePath,
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
      "--disable-quic", "--no-first-run", "--disable-component-update", "--disable-sync"],
    viewport: { width: 1100, height: 600 },
  });
  const page = await browser.newPage();
  page.on("console", (m) => console.log("page:", m.text()));
  await page.goto(url);
  // Waits until the page has drawn a full-size frame and asks for nothing more.
  const settled = async (fullFrames) => {
    await page.waitForFunction((n) => {
      const v = window.pshView;
      return v.fullFrames > n && !v.inFlight && !v.pending && v.full;
    }, fullFrames, { timeout: 120_000 });
  };
  await settled(0);
  const { width: W, height: H } = await page.evaluate(() => window.pshView.info);
  await page.screenshot({ path: path.join(shots, "start.png") });

  // Drag the camera: 60 pixels right and 25 down across the canvas.
  const box = await page.locator("#view").boundingBox();
  let n = await page.evaluate(() => window.pshView.fullFrames);
  await page.mouse.move(box.x + W / 2, box.y + H / 2);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) await page.mouse.move(box.x + W / 2 + 6 * k, box.y + H / 2 + 2.5 * k);
  await page.mouse.up();
  await settled(n);
  const dragged = await page.evaluate(() => ({ ...window.pshView.state, frames: window.pshView.frames, full: window.pshView.fullFrames }));
  check("dragging moved the camera", dragged.az !== 0 && dragged.el !== 0, `az ${dragged.az}, el ${dragged.el}`);
  check("dragging asked for half-size frames", dragged.frames > dragged.full, `${dragged.frames - dragged.full} of ${dragged.frames} frames`);

  // Turn the environment.
  n = dragged.full;
  await page.locator("#turn").fill("40");
  await settled(n);

  // Compares the canvas with `file` (a psh render PNG: the picture above its legend,
  // enlarged k times when narrow).
  const compare = async (name, file) => {
    const b64 = readFileSync(file).toString("base64");
    const result = await page.evaluate(async ({ b64, W, H }) => {
      const img = new Image();
      img.src = "data:image/png;base64," + b64;
      await img.decode();
      const c = new OffscreenCanvas(img.width, img.height);
      const x = c.getContext("2d");
      x.drawImage(img, 0, 0);
      const k = img.width / W;
      const png = x.getImageData(0, 0, img.width, img.height).data;
      const shown = document.getElementById("view").getContext("2d").getImageData(0, 0, W, H).data;
      let worst = 0, over = 0, steps = 0;
      for (let j = 0; j < H; j++) for (let i = 0; i < W; i++) {
        const a = 4 * (j * W + i), b = 4 * (j * k * img.width + i * k);
        let d = 0;
        for (let ch = 0; ch < 3; ch++) d = Math.max(d, Math.abs(shown[a + ch] - png[b + ch]));
        worst = Math.max(worst, d);
        if (d > 1) over++;
        if (d === 1) steps++;
      }
      return { worst, over, steps, k };
    }, { b64, W, H });
    const share = result.over / (W * H);
    check(`${name} equals psh render's within 1/255`, share <= 5e-4,
      `largest difference ${result.worst}/255; ${result.steps} pixels one step apart, ${result.over} more (${(100 * share).toFixed(3)}%)`);
  };

  const st = await page.evaluate(() => ({ ...window.pshView.state }));
  const out = path.join(tmp, "render");
  execFileSync(psh, ["render", ...sceneArgs, "--orbit", `${st.az},${st.el},${st.zoom}`,
    "--turn-environment", String(st.turn), "--polarizer", "30", "--out", out], { stdio: ["ignore", "ignore", "inherit"] });

  await compare("s0 after dragging and turning the environment", path.join(out, "render_s0.png"));
  await page.screenshot({ path: path.join(shots, "s0.png") });

  n = await page.evaluate(() => window.pshView.fullFrames);
  await page.selectOption("#show", "aop");
  await settled(n);
  await compare("AoLP", path.join(out, "render_aop.png"));
  await page.screenshot({ path: path.join(shots, "aop.png") });

  n = await page.evaluate(() => window.pshView.fullFrames);
  await page.selectOption("#show", "polarizer");
  await settled(n);
  const before = await page.evaluate(() => window.pshView.frames);
  await page.locator("#polarizer").fill("30");
  const after = await page.evaluate(() => window.pshView.frames);
  check("the polarizer turns without asking the server", before === after, `${after - before} frames asked`);
  await compare("through the polarizer at 30 degrees", path.join(out, "polarizer_30.png"));
  await page.screenshot({ path: path.join(shots, "polarizer.png") });

  // Save writes psh render's set into a new directory under --save-dir.
  await page.click("#save");
  await page.waitForFunction(() => document.getElementById("error").textContent.startsWith("saved"), null, { timeout: 120_000 });
  const saved = (await page.textContent("#error")).replace("saved: ", "");
  const files = ["render_s0.png", "render_aop.png", "render_s0.exr", "polarizer_30.png", "view.json"];
  const missing = files.filter((f) => { try { readFileSync(path.join(saved, f)); return false; } catch { return true; } });
  check("save wrote the view's pictures", missing.length === 0, missing.length ? `missing ${missing}` : saved);
  const { error } = await page.evaluate(() => ({ error: window.pshView.error }));
  check("the page reported no error", error === null, error || "");
} finally {
  await browser?.close();
  stopView(child);
  rmSync(tmp, { recursive: true, force: true });
}
console.log(`screenshots in ${shots}`);
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
