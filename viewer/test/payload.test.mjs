// The payload reader without a browser: arrays decoded and checked against their shapes, and the
// frame shown at a time (the last at or before it, held after the end).
import { it } from "node:test";
import assert from "node:assert/strict";
import { decodeArray, frameAt, PayloadError } from "../src/payload.js";

const b64 = (typed) => Buffer.from(typed.buffer).toString("base64");

it("decodes float32, float64 and uint8 arrays of the stated shape", () => {
  const values = new Float32Array([1.5, -2, 3.25, 4, 5, 6]);
  const a = decodeArray({ dtype: "float32", shape: [2, 3], b64: b64(values) }, "x", [2, 3]);
  assert.deepEqual(Array.from(a.data), [1.5, -2, 3.25, 4, 5, 6]);
  assert.deepEqual(a.shape, [2, 3]);
  const d = decodeArray({ dtype: "float64", shape: [2], b64: b64(new Float64Array([0.1, 1e300])) }, "t", [null]);
  assert.deepEqual(Array.from(d.data), [0.1, 1e300]);
  const u = decodeArray({ dtype: "uint8", shape: [3], b64: b64(new Uint8Array([0, 7, 255])) }, "m", [3]);
  assert.deepEqual(Array.from(u.data), [0, 7, 255]);
  assert.equal(decodeArray(null, "absent"), null);
});

it("names the array and the problem when it does not match its shape or type", () => {
  const values = b64(new Float32Array([1, 2, 3]));
  assert.throws(() => decodeArray({ dtype: "float32", shape: [4], b64: values }, "runs[0].time", [4]),
    (e) => e instanceof PayloadError && /runs\[0\]\.time: 12 bytes for shape \[4\]/.test(e.message));
  assert.throws(() => decodeArray({ dtype: "float32", shape: [3], b64: values }, "runs[0].base.position", [3, 3]),
    /runs\[0\]\.base\.position: shape \[3\], expected \[3,3\]/);
  assert.throws(() => decodeArray({ dtype: "int64", shape: [3], b64: values }, "q", null), /q: unknown dtype "int64"/);
});

it("shows the last frame at or before the time", () => {
  const time = new Float64Array([0, 0.05, 0.1, 0.15]);
  assert.equal(frameAt(time, -1), 0);
  assert.equal(frameAt(time, 0), 0);
  assert.equal(frameAt(time, 0.049), 0);
  assert.equal(frameAt(time, 0.05), 1);
  assert.equal(frameAt(time, 0.12), 2);
  assert.equal(frameAt(time, 0.15), 3);
  assert.equal(frameAt(time, 7), 3);
  assert.equal(frameAt(time, NaN), 0);
});
