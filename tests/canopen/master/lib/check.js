// How a scenario script ends: "PASS name" and status 0, or "FAIL name: reason" (one line) and
// status 1, after the cleanups (child processes killed by pid, buses closed) have run. A check
// that fails throws; nothing is retried.
'use strict';

const cleanups = [];

class CheckFailure extends Error {}

function check(condition, reason) {
  if (!condition) {
    throw new CheckFailure(reason);
  }
}

// Runs fn at the end of the script, last registered first, whether it passed or not.
function atEnd(fn) {
  cleanups.push(fn);
}

async function cleanUp() {
  while (cleanups.length) {
    try {
      await cleanups.pop()();
    } catch (e) {
      process.stderr.write(`cleanup: ${e.message}\n`);
    }
  }
}

function oneLine(text) {
  return String(text).replace(/\s*\n\s*/g, ' | ');
}

// Runs the scenario body; the process exits with its verdict (the library's timers would keep
// it alive otherwise).
function run(name, body) {
  body().then(async (summary) => {
    await cleanUp();
    console.log(`PASS ${name}${summary ? ': ' + summary : ''}`);
    process.exit(0);
  }, async (error) => {
    await cleanUp();
    const reason = error instanceof CheckFailure ? error.message : `${error.name}: ${error.message}`;
    console.log(`FAIL ${name}: ${oneLine(reason)}`);
    process.exit(1);
  });
}

module.exports = { check, atEnd, run, CheckFailure };
