// The npm canopen library (6.2.1, pinned by ../package-lock.json, installed by tools/setup into
// ../node_modules), loaded with lib/crc.js in place of its native dependency node-crc, which
// --ignore-scripts leaves unbuilt: require('node-crc') would throw "Could not locate the bindings
// file" and take the whole library with it. Everything else is the library's own code.
'use strict';

const path = require('path');
const { crc } = require('./crc');

const modules = path.join(__dirname, '..', 'node_modules');

function load() {
  let canopenDir;
  try {
    canopenDir = path.dirname(require.resolve('canopen/package.json', { paths: [modules] }));
  } catch (e) {
    throw new Error(`the npm canopen library is not installed in ${modules}: run tools/setup`);
  }
  const version = require(path.join(canopenDir, 'package.json')).version;
  if (version !== '6.2.1') {
    throw new Error(`npm canopen ${version} in ${modules}, expected 6.2.1 (package-lock.json): run tools/setup`);
  }
  // Resolved from where the library requires it, so the library finds this module in the cache.
  const nodeCrc = require.resolve('node-crc', { paths: [canopenDir] });
  if (!require.cache[nodeCrc]) {
    require.cache[nodeCrc] = { id: nodeCrc, filename: nodeCrc, loaded: true, exports: { crc } };
  }
  return require(canopenDir);
}

module.exports = load();
