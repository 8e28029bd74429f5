// Enough of PNG to look at a screenshot: 8-bit RGB or RGBA, not interlaced
// (what chromium's screenshots are), decoded with node's zlib.
import { inflateSync } from 'node:zlib';

function paeth(a, b, c) {
  const p = a + b - c;
  const pa = Math.abs(p - a);
  const pb = Math.abs(p - b);
  const pc = Math.abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/// {width, height, channels, pixels (Uint8Array, rows of width * channels)}.
export function decodePng(buffer) {
  const buf = Buffer.from(buffer);
  if (buf.readUInt32BE(0) !== 0x89504e47) throw new Error('not a PNG');
  let pos = 8;
  let width = 0;
  let height = 0;
  let channels = 0;
  const idat = [];
  while (pos < buf.length) {
    const length = buf.readUInt32BE(pos);
    const type = buf.toString('latin1', pos + 4, pos + 8);
    const data = buf.subarray(pos + 8, pos + 8 + length);
    if (type === 'IHDR') {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      const depth = data[8];
      const colour = data[9];
      if (depth !== 8 || (colour !== 2 && colour !== 6) || data[12] !== 0)
        throw new Error(`a PNG of depth ${depth}, colour type ${colour}, interlace ${data[12]}: not read here`);
      channels = colour === 6 ? 4 : 3;
    } else if (type === 'IDAT') idat.push(data);
    else if (type === 'IEND') break;
    pos += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = new Uint8Array(stride * height);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const src = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const row = y * stride;
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? pixels[row + x - channels] : 0;
      const b = y > 0 ? pixels[row - stride + x] : 0;
      const c = x >= channels && y > 0 ? pixels[row - stride + x - channels] : 0;
      const predictor = [0, a, b, (a + b) >> 1, paeth(a, b, c)][filter];
      if (predictor === undefined) throw new Error(`PNG filter ${filter} is not a filter`);
      pixels[row + x] = (src[x] + predictor) & 255;
    }
  }
  return { width, height, channels, pixels };
}

/// How much a picture shows: distinct colours (at 5 bits a channel) and the
/// share of the most common one (a blank or one-colour canvas is near 1).
export function pictureStats(png) {
  const counts = new Map();
  const n = png.width * png.height;
  for (let i = 0; i < n; ++i) {
    const p = i * png.channels;
    const key = ((png.pixels[p] >> 3) << 10) | ((png.pixels[p + 1] >> 3) << 5) | (png.pixels[p + 2] >> 3);
    counts.set(key, (counts.get(key) || 0) + 1);
  }
  let top = 0;
  for (const c of counts.values()) top = Math.max(top, c);
  return { colours: counts.size, topShare: top / n };
}
