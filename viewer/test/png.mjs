// Decodes the PNG screenshots chromium writes (8-bit RGB or RGBA, not interlaced) into RGBA pixels,
// so the tests need no image package.
import zlib from "node:zlib";

export function decodePng(buffer) {
  const signature = "89504e470d0a1a0a";
  if (buffer.subarray(0, 8).toString("hex") !== signature) throw new Error("not a PNG");
  let offset = 8;
  let width = 0, height = 0, colorType = 0;
  const idat = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString("ascii", offset + 4, offset + 8);
    const data = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === "IHDR") {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      const bitDepth = data[8];
      colorType = data[9];
      if (bitDepth !== 8 || (colorType !== 2 && colorType !== 6) || data[12] !== 0) {
        throw new Error(`PNG of bit depth ${bitDepth}, colour type ${colorType}, interlace ${data[12]}: not decoded here`);
      }
    } else if (type === "IDAT") {
      idat.push(data);
    } else if (type === "IEND") {
      break;
    }
    offset += 12 + length;
  }
  const channels = colorType === 6 ? 4 : 3;
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = new Uint8Array(width * height * 4);
  let previous = new Uint8Array(stride);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const current = new Uint8Array(stride);
    for (let x = 0; x < stride; x++) {
      const a = x >= channels ? current[x - channels] : 0;
      const b = previous[x];
      const c = x >= channels ? previous[x - channels] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      current[x] = (line[x] + predictor) & 0xff;
    }
    for (let x = 0; x < width; x++) {
      pixels.set(current.subarray(x * channels, x * channels + 3), (y * width + x) * 4);
      pixels[(y * width + x) * 4 + 3] = channels === 4 ? current[x * channels + 3] : 255;
    }
    previous = current;
  }
  return { width, height, pixels };
}

// Number of distinct RGB colours.
export function distinctColours(image) {
  const seen = new Set();
  for (let i = 0; i < image.pixels.length; i += 4) {
    seen.add((image.pixels[i] << 16) | (image.pixels[i + 1] << 8) | image.pixels[i + 2]);
  }
  return seen.size;
}

// Share of pixels equal (within 8 per channel) to the colour of the top-left pixel.
export function shareLikeCorner(image) {
  const p = image.pixels;
  let same = 0;
  for (let i = 0; i < p.length; i += 4) {
    if (Math.abs(p[i] - p[0]) <= 8 && Math.abs(p[i + 1] - p[1]) <= 8 && Math.abs(p[i + 2] - p[2]) <= 8) same++;
  }
  return same / (p.length / 4);
}

// Mean absolute difference per channel (0..255) of two images over the square of half-width
// `radius` px around (cx, cy), clipped to the image.
export function regionDifference(a, b, [cx, cy], radius) {
  let sum = 0, count = 0;
  for (let y = Math.max(0, Math.round(cy - radius)); y <= Math.min(a.height - 1, Math.round(cy + radius)); y++) {
    for (let x = Math.max(0, Math.round(cx - radius)); x <= Math.min(a.width - 1, Math.round(cx + radius)); x++) {
      const i = (y * a.width + x) * 4;
      for (let ch = 0; ch < 3; ch++) sum += Math.abs(a.pixels[i + ch] - b.pixels[i + ch]);
      count += 3;
    }
  }
  return count ? sum / count : 0;
}
