// What the page reports: the #stats element's JSON (read by scripted runs
// and the browser test) and the one-line error banner.
export class Status {
  constructor(statsElement, bannerElement) {
    this.element = statsElement;
    this.banner = bannerElement;
    this.values = {
      fps: 0, bodies: 0, fragments: 0, bonds_broken: 0, physics_ms: 0, break_ms: 0, fracture_ms: 0, fracture_call_ms: 0,
      tree_hash: null, frames: 0, shots: 0, scene: null, error: null, ready: false, done: false,
    };
    this.frameTimes = [];
    this.write();
  }

  // Frames drawn in the last second; frozen once a scripted run is done.
  tick(now) {
    if (this.values.done) return;
    this.frameTimes.push(now);
    while (this.frameTimes.length && now - this.frameTimes[0] > 1000) this.frameTimes.shift();
    const span = now - this.frameTimes[0];
    if (this.frameTimes.length > 1 && span > 0) this.values.fps = round(((this.frameTimes.length - 1) * 1000) / span, 1);
  }

  set(values) {
    Object.assign(this.values, values);
  }

  write() {
    this.element.textContent = JSON.stringify(this.values);
  }

  // One line naming the problem, on the page and in stats.error.
  error(e) {
    const message = String(e?.message ?? e).split('\n')[0];
    this.values.error = message;
    this.banner.textContent = message;
    this.banner.hidden = false;
    this.write();
  }

  clearError() {
    this.banner.hidden = true;
  }
}

export const round = (v, digits = 2) => Math.round(v * 10 ** digits) / 10 ** digits;
