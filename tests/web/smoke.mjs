// Drives the browser build of the viewer in Debian's headless Chromium:
//   node tests/web/smoke.mjs BASE_URL SCREENSHOT_DIR
// The page publishes its state as data-rigid-* attributes of <body> (src/web.rs); the
// checks read those and the pixels of screenshots. Exit code 0 only if every check passed.
import { mkdirSync } from "node:fs";
import { join } from "node:path";
import { chromium } from "playwright-core";
import { PNG } from "pngjs";

const [base, shots] = process.argv.slice(2);
mkdirSync(shots, { recursive: true });

// The flags Chromium needs on a machine with no network and no GPU (WebGL2 then runs on
// SwiftShader); each check gets a fresh profile.
const FLAGS = ["--headless", "--no-sandbox", "--no-first-run", "--disable-background-networking",
  "--disable-component-update", "--disable-sync"];
const VIEWPORT = { width: 1280, height: 720 };
// Where egui lays out the panel at this size (src/ui/panel.rs: scene row, then spawn row).
const PAUSE_BUTTON = { x: 33, y: 59 };
const SPAWN_BOX_BUTTON = { x: 90, y: 279 };
const PANEL_WIDTH = 290;

let passed = 0;
let failed = 0;

async function check(name, extraFlags, body, viewport = VIEWPORT) {
  const browser = await chromium.launch({ executablePath: "/usr/bin/chromium", args: [...FLAGS, ...extraFlags] });
  const page = await browser.newPage({ viewport });
  const log = [];
  page.on("console", (m) => log.push(`${m.type()}: ${m.text().slice(0, 400)}`));
  page.on("pageerror", (e) => log.push(`pageerror: ${e.message}`));
  try {
    await body(page);
    passed++;
    console.log(`ok   ${name}`);
  } catch (error) {
    failed++;
    console.log(`FAIL ${name}: ${error.message}`);
    console.log(log.filter((l) => !l.includes("GL Driver Message")).map((l) => "     " + l).join("\n"));
    await page.screenshot({ path: join(shots, `${name}-failed.png`) }).catch(() => {});
  } finally {
    await browser.close();
  }
}

const status = (page) => page.evaluate(() => ({ ...document.body.dataset }));

async function waitFor(page, what, accept, seconds = 90) {
  const deadline = Date.now() + seconds * 1000;
  for (;;) {
    const s = await status(page);
    if (accept(s)) return s;
    if (s.rigidState === "failed") {
      const message = await page.textContent("#rigid-message");
      throw new Error(`the page failed while waiting for ${what}: ${message}`);
    }
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}: ${JSON.stringify(s)}`);
    await page.waitForTimeout(200);
  }
}

/// Pixels of the 3D view (right of the panel) that `accept(r, g, b)` picks; `from` and `to`
/// bound the columns counted.
async function countPixels(page, file, accept, from = PANEL_WIDTH, to = Infinity) {
  const png = PNG.sync.read(await page.screenshot({ path: join(shots, file) }));
  let count = 0;
  for (let y = 0; y < png.height; y++) {
    for (let x = from; x < Math.min(png.width, to); x++) {
      const i = 4 * (y * png.width + x);
      if (accept(png.data[i], png.data[i + 1], png.data[i + 2])) count++;
    }
  }
  return count;
}

// Dynamic bodies are drawn in saturated colours (src/render/renderer.rs: PALETTE and
// SLEEP_COLOR, 80 or more between the largest and smallest channel even on shaded faces);
// the sky, the grid and static bodies are grey or pale (at most 70).
const bodyColour = (r, g, b) => Math.max(r, g, b) - Math.min(r, g, b) >= 80;

await check("falling-box", [], async (page) => {
  await page.goto(base);
  const running = await waitFor(page, "60 steps", (s) => s.rigidState === "running" && Number(s.rigidSteps) >= 60);
  console.log(`     drawing on ${running.rigidAdapter}`);
  if (running.rigidScene !== "falling_box" || running.rigidBodies !== "3") {
    throw new Error(`expected the falling box (3 bodies), got ${JSON.stringify(running)}`);
  }
  const pixels = await countPixels(page, "falling-box.png", bodyColour);
  // The falling box covers about 4000 pixels at this size; a missing body leaves none.
  if (pixels < 1000) throw new Error(`the falling box is not drawn: ${pixels} body-coloured pixels`);
  console.log(`     falling box: ${pixels} body-coloured pixels`);

  await page.mouse.click(SPAWN_BOX_BUTTON.x, SPAWN_BOX_BUTTON.y);
  await waitFor(page, "the spawned box", (s) => s.rigidBodies === "4", 20);
  await page.mouse.click(PAUSE_BUTTON.x, PAUSE_BUTTON.y);
  const paused = await waitFor(page, "the pause", (s) => s.rigidPaused === "true", 20);
  await page.waitForTimeout(1000);
  const later = await status(page);
  if (later.rigidSteps !== paused.rigidSteps) {
    throw new Error(`paused, yet steps went from ${paused.rigidSteps} to ${later.rigidSteps}`);
  }
  await page.screenshot({ path: join(shots, "falling-box-spawned.png") });
});

await check("pachinko", [], async (page) => {
  await page.goto(`${base}?scene=pachinko`);
  const s = await waitFor(page, "pachinko running", (s) => s.rigidState === "running" && Number(s.rigidSteps) >= 60);
  if (s.rigidScene !== "pachinko" || Number(s.rigidBodies) < 50) {
    throw new Error(`expected the pachinko board, got ${JSON.stringify(s)}`);
  }
  const pixels = await countPixels(page, "pachinko.png", bodyColour);
  if (pixels < 200) throw new Error(`no balls drawn: ${pixels} body-coloured pixels`);
  console.log(`     pachinko: ${s.rigidBodies} bodies, ${pixels} body-coloured pixels`);
});

// A phone: the panel starts folded and the scene fills the width; two fingers spreading
// apart zoom in (the asleep pyramid, which does not move, covers more pixels), one finger
// orbits (most of the view changes), and a tap on "» Controls" unfolds the panel.
const PHONE = { width: 390, height: 844 };
await check("phone", [], async (page) => {
  const cdp = await page.context().newCDPSession(page);
  await cdp.send("Emulation.setTouchEmulationEnabled", { enabled: true, maxTouchPoints: 5 });
  await page.goto(`${base}?scene=pyramid`);
  await waitFor(page, "the pyramid running", (s) => s.rigidState === "running" && Number(s.rigidSteps) >= 30);
  // The panel's background is a dark grey (egui's dark theme); the sky and the floor are pale.
  const dark = (r, g, b) => Math.max(r, g, b) < 45;
  const panelArea = PANEL_WIDTH * PHONE.height;
  const folded = await countPixels(page, "phone-folded.png", dark, 0, PANEL_WIDTH);
  if (folded > 0.05 * panelArea) throw new Error(`the panel is not folded: ${folded} dark pixels`);
  const touches = async (type, points) => {
    await cdp.send("Input.dispatchTouchEvent", {
      type,
      touchPoints: points.map(([x, y], id) => ({ x, y, id, radiusX: 1, radiusY: 1, force: 1 })),
    });
    await page.waitForTimeout(50);
  };
  const drawn = () => countPixels(page, "phone-before-pinch.png", bodyColour, 0);
  const before = await drawn();
  await touches("touchStart", [[150, 500], [240, 500]]);
  for (let k = 1; k <= 10; k++) await touches("touchMove", [[150 - 6 * k, 500], [240 + 6 * k, 500]]);
  await touches("touchEnd", []);
  await page.waitForTimeout(500);
  const after = await countPixels(page, "phone-pinched.png", bodyColour, 0);
  if (!(after > 1.5 * before)) throw new Error(`the pinch did not zoom in: ${before} then ${after} body pixels`);
  const image = async (file) => PNG.sync.read(await page.screenshot({ path: join(shots, file) }));
  const still = await image("phone-before-orbit.png");
  await touches("touchStart", [[200, 120]]);
  for (let k = 1; k <= 10; k++) await touches("touchMove", [[200 + 12 * k, 120]]);
  await touches("touchEnd", []);
  await page.waitForTimeout(500);
  const orbited = await image("phone-orbited.png");
  let changed = 0;
  for (let i = 0; i < still.data.length; i += 4) {
    const d = Math.abs(still.data[i] - orbited.data[i]) + Math.abs(still.data[i + 1] - orbited.data[i + 1]);
    if (d > 30) changed++;
  }
  const share = changed / (still.width * still.height);
  if (share < 0.05) throw new Error(`one finger did not orbit: ${(100 * share).toFixed(1)} % of the view changed`);
  await touches("touchStart", [[30, 18]]);
  await touches("touchEnd", []);
  await page.waitForTimeout(500);
  const unfolded = await countPixels(page, "phone-unfolded.png", dark, 0, PANEL_WIDTH);
  if (unfolded < 0.5 * panelArea) throw new Error(`the tap did not unfold the panel: ${unfolded} dark pixels`);
  console.log(`     phone: ${folded} then ${unfolded} dark pixels where the panel goes; pinch ${before} → ${after} body pixels; orbit changed ${(100 * share).toFixed(0)} %`);
}, PHONE);

await check("unknown-scene", [], async (page) => {
  await page.goto(`${base}?scene=no_such_scene`);
  await waitFor(page, "the failure", (s) => s.rigidState !== "loading", 60).catch(() => {});
  const message = await page.textContent("#rigid-message");
  if (!message.includes("no_such_scene")) throw new Error(`no message names the scene: "${message}"`);
});

// Without WebGL (and with no WebGPU adapter) there is nothing to draw with: the page says so.
await check("no-graphics", ["--disable-3d-apis"], async (page) => {
  await page.goto(base);
  const deadline = Date.now() + 60_000;
  while ((await status(page)).rigidState !== "failed") {
    if (Date.now() > deadline) throw new Error(`no failure shown: ${JSON.stringify(await status(page))}`);
    await page.waitForTimeout(200);
  }
  const message = await page.textContent("#rigid-message");
  if (!/neither WebGPU nor WebGL2/.test(message)) throw new Error(`unclear message: "${message}"`);
  if (!(await page.isVisible("#rigid-message"))) throw new Error("the message is not visible");
  await page.screenshot({ path: join(shots, "no-graphics.png") });
  console.log(`     shown: ${message.slice(0, 90)}…`);
});

console.log(`web: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
