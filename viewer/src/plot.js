// The plot under the 3D view: uPlot draws the selected series columns (one y scale per unit,
// axes for the first two units), a vertical cursor line marks the shown frame's time, and a
// column picker (checkboxes) chooses the columns.
import uPlot from 'uplot';

const PALETTE = ['#6cb4ff', '#ff8a5c', '#7ddc7a', '#e07ce8', '#ffd24a', '#5ce0d6', '#ff6b8a', '#b7a3ff', '#c9e265', '#f0a35e'];

function unitScale(unit) {
  return 'u:' + (unit || '1');
}

export class Plot {
  // columns: [{name, unit}]; selected: [names]; onSeek(t) when the plot is clicked (run mode)
  constructor(container, pickerContainer, { columns, selected, onSeek, live }) {
    this.container = container;
    this.picker = pickerContainer;
    this.columns = columns;
    this.byName = new Map(columns.map((c, i) => [c.name, { ...c, index: i }]));
    this.swatches = new Map();
    this.selected = selected.filter((n) => this.byName.has(n));
    this.onSeek = onSeek;
    this.live = !!live;
    this.time = [];
    this.values = new Map(columns.map((c) => [c.name, []]));
    this.cursorT = null;
    this.xRange = null;
    this.u = null;
    this.cursorEl = document.createElement('div');
    this.cursorEl.className = 'tb-cursor';
    this.cursorEl.hidden = true;
    this._buildPicker();
    this._build();
    this.containerObserver = new ResizeObserver(() => this._resize());
    this.containerObserver.observe(container);
  }

  destroy() {
    this.containerObserver.disconnect();
    if (this.legendObserver) this.legendObserver.disconnect();
    if (this.u) this.u.destroy();
    this.u = null;
  }

  _buildPicker() {
    this.picker.textContent = '';
    for (const c of this.columns) {
      const label = document.createElement('label');
      const box = document.createElement('input');
      box.type = 'checkbox';
      box.value = c.name;
      box.dataset.column = c.name;
      box.checked = this.selected.includes(c.name);
      box.addEventListener('change', () => {
        const names = [...this.picker.querySelectorAll('input[type=checkbox]')].filter((b) => b.checked).map((b) => b.value);
        this.selected = names;
        this._build();
      });
      const swatch = document.createElement('span');
      swatch.style.cssText = 'display:inline-block;width:8px;height:8px;border-radius:2px;flex:none';
      this.swatches.set(c.name, swatch);
      const text = document.createElement('span');
      text.textContent = c.name;
      const unit = document.createElement('span');
      unit.className = 'unit';
      unit.textContent = c.unit ? `(${c.unit})` : '';
      label.title = c.name + (c.unit ? ` [${c.unit}]` : '');
      label.append(box, swatch, text, unit);
      this.picker.append(label);
    }
  }

  _size() {
    const legend = this.u && this.u.root.querySelector('.u-legend');
    const legendAllowance = legend ? legend.offsetHeight + 4 : 26;
    return {
      width: Math.max(100, this.container.clientWidth - 4),
      height: Math.max(110, this.container.clientHeight - legendAllowance),
    };
  }

  _build() {
    if (this.u) {
      this.u.destroy();
      this.u = null;
    }
    // Colours follow the selection order, so the plotted lines never share a colour (up to 10).
    const cols = this.selected.map((n, i) => ({ ...this.byName.get(n), color: PALETTE[i % PALETTE.length] }));
    for (const [name, sw] of this.swatches) {
      const c = cols.find((x) => x.name === name);
      sw.style.background = c ? c.color : 'transparent';
      sw.style.outline = c ? 'none' : '1px solid #56606d';
    }
    const units = [...new Set(cols.map((c) => c.unit || '1'))];
    const scales = { x: { time: false } };
    for (const unit of units) scales[unitScale(unit)] = { auto: true };
    if (this.live) scales.x.auto = false;
    const axisStyle = {
      stroke: '#a9b4c2',
      grid: { stroke: 'rgba(255,255,255,0.07)', width: 1 },
      ticks: { stroke: 'rgba(255,255,255,0.15)', width: 1 },
      font: '11px system-ui, sans-serif',
    };
    const axes = [{ ...axisStyle, label: 't (s)', labelSize: 14, labelFont: '11px system-ui, sans-serif', size: 34 }];
    units.slice(0, 2).forEach((unit, i) => {
      axes.push({
        ...axisStyle,
        scale: unitScale(unit),
        side: i === 0 ? 3 : 1,
        label: unit,
        labelSize: 14,
        labelFont: '11px system-ui, sans-serif',
        size: 52,
        grid: i === 0 ? axisStyle.grid : { show: false },
      });
    });
    if (units.length === 0) axes.push({ ...axisStyle, scale: 'u:1', side: 3, size: 52 });
    const series = [{ label: 't (s)', value: (u, v) => (v == null ? '–' : v.toFixed(2)) }];
    for (const c of cols) {
      series.push({
        label: c.name + (c.unit ? ` (${c.unit})` : ''),
        scale: unitScale(c.unit),
        stroke: c.color,
        width: 1.5,
        spanGaps: false,
        points: { show: false },
        value: (u, v) => (v == null ? '–' : Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(3) : v.toPrecision(4)),
      });
    }
    if (cols.length === 0) series.push({ label: '(no column selected)', scale: 'u:1', stroke: 'transparent' });
    const opts = {
      ...this._size(),
      scales,
      axes,
      series,
      legend: { show: true, live: !this.live },
      cursor: { drag: { x: !this.live, y: false }, points: { show: false }, y: false },
      hooks: {
        setScale: [() => this._placeCursor()],
        setSize: [() => this._placeCursor()],
        ready: [(u) => {
          u.over.append(this.cursorEl);
          this._placeCursor();
        }],
      },
    };
    this.u = new uPlot(opts, this._data(), this.container);
    // The legend's height (it wraps when many columns are plotted) sets the plot's height.
    if (this.legendObserver) this.legendObserver.disconnect();
    const legend = this.u.root.querySelector('.u-legend');
    if (legend) {
      this.legendObserver = new ResizeObserver(() => this._resize());
      this.legendObserver.observe(legend);
    }
    if (this.live && this.xRange) this.u.setScale('x', { min: this.xRange[0], max: this.xRange[1] });
    this._legendIdx = null;
    this.hovering = false;
    this.u.over.addEventListener('mouseenter', () => { this.hovering = true; });
    this.u.over.addEventListener('mouseleave', () => {
      this.hovering = false;
      this._legendIdx = null;
      this._placeCursor();
    });
    if (!this.live && this.onSeek) {
      let down = null;
      this.u.over.addEventListener('mousedown', (e) => { down = [e.clientX, e.clientY]; });
      this.u.over.addEventListener('mouseup', (e) => {
        if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 3) return;
        const rect = this.u.over.getBoundingClientRect();
        const t = this.u.posToVal(e.clientX - rect.left, 'x');
        if (Number.isFinite(t)) this.onSeek(t);
      });
    }
  }

  _data() {
    const d = [this.time];
    if (this.selected.length === 0) d.push(this.time.map(() => null));
    for (const n of this.selected) d.push(this.values.get(n));
    return d;
  }

  _resize() {
    if (!this.u) return;
    const size = this._size();
    if (size.width !== this.u.width || size.height !== this.u.height) this.u.setSize(size);
  }

  // Run mode: the whole series at once.
  setData(time, columnsValues) {
    this.time = time;
    for (const [name, vals] of columnsValues) this.values.set(name, vals);
    if (this.u) this.u.setData(this._data(), true);
  }

  // Live mode: one sample; keeps the last `windowS` seconds. Redraws at most ~10 times a second.
  push(t, values, windowS = 10) {
    const n = this.time.length;
    if (n && t < this.time[n - 1] - 1e-9) this.clear(); // a reset: time went back
    this.time.push(t);
    for (const [name, arr] of this.values) {
      const v = values ? values[name] : undefined;
      arr.push(typeof v === 'number' && Number.isFinite(v) ? v : null);
    }
    let drop = 0;
    while (drop < this.time.length && this.time[drop] < t - windowS * 1.1) drop++;
    if (drop > 64 || (drop > 0 && this.time.length > 4096)) {
      this.time.splice(0, drop);
      for (const arr of this.values.values()) arr.splice(0, drop);
    }
    this.xRange = [Math.max(0, t - windowS), Math.max(windowS, t)];
    const now = performance.now();
    if (!this._lastDraw || now - this._lastDraw > 100) {
      this._lastDraw = now;
      if (this.u) {
        this.u.setData(this._data(), false);
        this.u.setScale('x', { min: this.xRange[0], max: this.xRange[1] });
      }
    }
  }

  clear() {
    this.time = [];
    for (const k of this.values.keys()) this.values.set(k, []);
    if (this.u) this.u.setData(this._data(), false);
  }

  setCursor(t) {
    this.cursorT = t;
    this._placeCursor();
  }

  _placeCursor() {
    const u = this.u;
    if (!u || this.cursorT == null || !Number.isFinite(this.cursorT)) {
      this.cursorEl.hidden = true;
      return;
    }
    const x = u.valToPos(this.cursorT, 'x');
    const w = u.over.clientWidth || u.bbox.width / (window.devicePixelRatio || 1);
    if (!Number.isFinite(x) || x < -1 || x > w + 1) {
      this.cursorEl.hidden = true;
      return;
    }
    this.cursorEl.hidden = false;
    this.cursorEl.style.left = `${x - 1}px`;
    // The legend shows the values at the shown frame unless the mouse is over the plot.
    if (!this.live && !this.hovering && this.time.length) {
      let idx = 0;
      let hi = this.time.length - 1;
      while (idx < hi) {
        const mid = (idx + hi + 1) >> 1;
        if (this.time[mid] <= this.cursorT + 1e-9) idx = mid;
        else hi = mid - 1;
      }
      if (idx !== this._legendIdx) {
        this._legendIdx = idx;
        u.setLegend({ idx });
      }
    }
  }
}
