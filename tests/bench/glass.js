#!/usr/bin/env node
/*
 * glass.js — the map's live video, glass to glass, read from the frame code
 * imagerd burns into each frame ([overlay] frame_code: 20 black-or-white
 * 12-pixel cells along the bottom edge, the frame number, most significant
 * bit first). Headless Chromium opens stationd's page; at every frame the
 * video element presents (requestVideoFrameCallback), the frame is drawn
 * into a canvas and the cells' centres are read back. Prints one JSON line
 * per frame shown: {"n": FRAME_NUMBER, "t": WALL_MS} (the frame's expected
 * display time, Unix milliseconds), and "# ..." comments.
 *
 * Usage: node glass.js --url URL --chromium PATH --seconds S
 */
'use strict';
const path = require('path');
const CHROMIUM_ARGS = require('../browser/chromium_args.js');
const { chromium } = require(path.join(__dirname, '../browser/node_modules/playwright-core'));

const opt = {};
for (let i = 2; i + 1 < process.argv.length; i += 2) opt[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];

(async () => {
  const browser = await chromium.launch({ executablePath: opt.chromium, headless: true, args: CHROMIUM_ARGS });
  try {
    const page = await browser.newPage({ viewport: { width: 1600, height: 1000 } });
    await page.goto(opt.url);
    await page.waitForFunction(() => {
      const v = document.getElementById('sensor-video');
      return v && !v.hidden && v.videoWidth > 0 && v.currentTime > 0;
    }, null, { timeout: 60000 });
    const size = await page.evaluate(() => {
      const v = document.getElementById('sensor-video');
      return [v.videoWidth, v.videoHeight];
    });
    console.log('# playing ' + size[0] + ' x ' + size[1]);
    await page.evaluate(() => {
      const BITS = 20, CELL = 12;
      const v = document.getElementById('sensor-video');
      const c = document.createElement('canvas');
      c.width = v.videoWidth;
      c.height = v.videoHeight;
      const g = c.getContext('2d', { willReadFrequently: true });
      window.__shown = [];
      const cb = (now, md) => {
        g.drawImage(v, 0, 0, c.width, c.height);
        const y = c.height - CELL;
        const row = g.getImageData(0, y, (BITS + 1) * CELL, 1).data;
        let n = 0;
        for (let b = 0; b < BITS; b++) {
          const x = CELL / 2 + b * CELL + CELL / 2;
          n = n * 2 + ((row[4 * x] + row[4 * x + 1] + row[4 * x + 2]) / 3 > 127.5 ? 1 : 0);
        }
        window.__shown.push({ n, t: performance.timeOrigin + md.expectedDisplayTime });
        v.requestVideoFrameCallback(cb);
      };
      v.requestVideoFrameCallback(cb);
    });
    await new Promise((r) => setTimeout(r, 1000 * Number(opt.seconds || 20)));
    const shown = await page.evaluate(() => window.__shown);
    for (const s of shown) console.log(JSON.stringify(s));
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error('glass.js: ' + e.message);
  process.exit(1);
});
