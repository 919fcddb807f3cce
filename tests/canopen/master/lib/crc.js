// A pure-JavaScript stand-in for node-crc's crc(), the one function of it the npm canopen library
// calls (source/functions/crc.js: the CRC-16 of SDO block transfers, CiA 301 7.2.4.3.16). node-crc
// is a native addon built by an install script, and the tests install with --ignore-scripts
// (tools/setup): nothing is compiled, and the library still loads (lib/canopen.js).
'use strict';

// crc(bits, reflection, expL, expH, iniL, iniH, fixL, fixH, data) as node-crc declares it
// (index.d.ts): polynomial `exp` (already bit-reversed when `reflection`), initial value `ini`,
// final XOR `fix`, the result big-endian in bits/8 bytes. Widths 8, 16, 24 and 32 only: the
// high words (for 64 bits) must be 0.
function crc(bits, reflection, expL, expH, iniL, iniH, fixL, fixH, data) {
  if (![8, 16, 24, 32].includes(bits) || expH || iniH || fixH) {
    throw new RangeError(`crc: ${bits}-bit CRCs are not implemented here (8, 16, 24 or 32)`);
  }
  if (!Buffer.isBuffer(data)) {
    throw new TypeError('crc: data must be a Buffer');
  }
  const mask = bits === 32 ? 0xFFFFFFFF : (1 << bits) - 1;
  const top = 2 ** (bits - 1);
  let value = iniL >>> 0;
  for (const byte of data) {
    if (reflection) {
      value = (value ^ byte) >>> 0;
      for (let i = 0; i < 8; ++i) {
        value = value & 1 ? ((value >>> 1) ^ expL) >>> 0 : value >>> 1;
      }
    } else {
      value = (value ^ (byte * 2 ** (bits - 8))) >>> 0;
      for (let i = 0; i < 8; ++i) {
        value = value >= top ? (((value - top) * 2) ^ expL) >>> 0 : value * 2;
      }
    }
    value = (value & mask) >>> 0;
  }
  value = ((value ^ fixL) & mask) >>> 0;
  const out = Buffer.alloc(bits / 8);
  out.writeUIntBE(value, 0, bits / 8);
  return out;
}

module.exports = { crc };
