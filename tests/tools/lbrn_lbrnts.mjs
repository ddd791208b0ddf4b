// Read a LightBurn project with the npm package lbrnts and print what it
// sees as JSON: each layer's settings and every ellipse (centre, radii,
// layer), groups included. Usage: node lbrn_lbrnts.mjs LBRNTS_INDEX FILE
import fs from "fs";
import { pathToFileURL } from "url";

const lbrnts = await import(pathToFileURL(process.argv[2]).href);
const project = lbrnts.LightBurnProject.parse(fs.readFileSync(process.argv[3], "utf8"));
const settings = [];
const ellipses = [];
const walk = (children) => {
  for (const c of children) {
    if (c.token === "CutSetting") {
      settings.push({ index: c.index, name: c.name, speed: c.speed, power: c.maxPower, passes: c.numPasses });
    } else if (c.token === "Shape.Ellipse") {
      ellipses.push({ cut: c.cutIndex, x: c.xform[4], y: c.xform[5], rx: c.rx, ry: c.ry });
    } else if (c.children) {
      walk(c.children);
    }
  }
};
walk(project.children);
console.log(JSON.stringify({ settings, ellipses }));
