// The plot panel: torso height, forward distance, one joint (chosen in a select) and the contacts'
// normal forces against time, every run on one time axis, with a vertical cursor at the current time.
// A click on a plot moves the time there.
import uPlot from "uplot";

const HEIGHT = 118; // px per plot: the four fit beside a 720 px high view
const CONTACT_COLORS = ["#e8590c", "#1971c2", "#2f9e44", "#9c36b5", "#f08c00", "#0c8599", "#c2255c", "#5c940d"];

function cursorPlugin(getTime) {
  return {
    hooks: {
      draw: [(u) => {
        const t = getTime();
        const x = u.valToPos(t, "x", true);
        if (!Number.isFinite(x)) return;
        const ctx = u.ctx;
        ctx.save();
        ctx.strokeStyle = "#e03131";
        ctx.lineWidth = 1.5 * devicePixelRatio;
        ctx.beginPath();
        ctx.moveTo(x, u.bbox.top);
        ctx.lineTo(x, u.bbox.top + u.bbox.height);
        ctx.stroke();
        ctx.restore();
      }],
    },
  };
}

// Columns of one run on its own time axis -> one table per run for uPlot.join.
function table(run, columns) {
  return [Array.from(run.time), ...columns.map((c) => (c ? Array.from(c) : new Array(run.frames).fill(null)))];
}

function strided(data, frames, stride, offset) {
  if (!data) return null;
  const out = new Float64Array(frames);
  for (let i = 0; i < frames; i++) out[i] = data[i * stride + offset];
  return out;
}

export class PlotPanel {
  // runs: decoded runs; colors: CSS colour per run; container: the element to fill.
  constructor(runs, colors, container, getTime, onSeek) {
    this.runs = runs;
    this.colors = colors;
    this.getTime = getTime;
    this.onSeek = onSeek;
    this.container = container;
    this.plots = [];
    const jointNames = [...new Set(runs.flatMap((r) => r.joints.names))];
    this.jointNames = jointNames;

    this.addPlot("torso height (m)", runs.map((r) => r.series.torsoHeight));
    this.addPlot("forward distance (m)", runs.map((r) => r.series.forwardDistance));

    const select = document.createElement("select");
    select.id = "nmdp-view-joint";
    for (const name of jointNames) select.add(new Option(name, name));
    // The first actuated joint, not a base coordinate, is the useful default.
    const firstActuated = jointNames.find((n) => !n.startsWith("base_")) || jointNames[0];
    if (firstActuated) select.value = firstActuated;
    select.addEventListener("change", () => this.setJoint(select.value));
    this.jointSelect = select;
    const label = document.createElement("label");
    label.className = "nmdp-view-select";
    label.append("joint ", select);
    container.append(label);
    this.jointPlot = this.addPlot("joint (rad or m)", runs.map((r) => this.jointColumn(r, select.value)));

    const forceColumns = [];
    const forceSeries = [];
    runs.forEach((run, k) => {
      const c = run.contacts.names.length;
      run.contacts.names.forEach((name, j) => {
        forceColumns.push({ run: k, data: strided(run.contacts.normalForce, run.frames, c, j) });
        forceSeries.push({
          label: runs.length > 1 ? `${name} (${k + 1})` : name,
          stroke: CONTACT_COLORS[j % CONTACT_COLORS.length],
          dash: k > 0 ? [6, 4] : undefined,
          width: 1.2,
        });
      });
    });
    const anyForce = forceColumns.some((c) => c.data);
    this.addPlot(anyForce ? "normal force (N)" : "normal force (N): not in the run files", null,
      { columns: forceColumns, series: forceSeries });
  }

  jointColumn(run, name) {
    const j = run.joints.names.indexOf(name);
    return j < 0 ? null : strided(run.joints.q, run.frames, run.joints.names.length, j);
  }

  // perRun: one column per run, or custom {columns: [{run, data}], series} for several per run.
  addPlot(title, perRun, custom) {
    const columns = custom ? custom.columns : perRun.map((data, k) => ({ run: k, data }));
    const series = custom ? custom.series : this.runs.map((run, k) => ({
      label: this.runs.length > 1 ? `run ${k + 1}` : title.replace(/ \(.*\)$/, ""),
      stroke: this.colors[k], width: 1.5,
    }));
    const data = this.join(columns);
    const heading = document.createElement("div");
    heading.className = "nmdp-view-plot-title";
    heading.textContent = title;
    const holder = document.createElement("div");
    this.container.append(heading, holder);
    const plot = new uPlot({
      width: this.width(), height: HEIGHT,
      scales: { x: { time: false } },
      axes: [{ size: 28 }, { size: 48 }],
      series: [{ label: "t (s)" }, ...series],
      legend: { show: series.length > 1 },
      plugins: [cursorPlugin(this.getTime)],
      cursor: { drag: { x: false, y: false } },
    }, data, holder);
    plot.over.addEventListener("click", () => {
      const t = plot.posToVal(plot.cursor.left, "x");
      if (Number.isFinite(t)) this.onSeek(t);
    });
    const entry = { plot, columns, heading };
    this.plots.push(entry);
    return entry;
  }

  // One x column (the union of the runs' times) and one y column per series, null where a run has
  // no sample.
  join(columns) {
    const tables = this.runs.map((run, k) => table(run, columns.filter((c) => c.run === k).map((c) => c.data)));
    const joined = uPlot.join(tables);
    return joined;
  }

  setJoint(name) {
    const columns = this.runs.map((run, k) => ({ run: k, data: this.jointColumn(run, name) }));
    this.jointPlot.columns = columns;
    this.jointPlot.plot.setData(this.join(columns));
  }

  width() {
    return Math.max(200, this.container.clientWidth - 16);
  }

  resize() {
    for (const { plot } of this.plots) plot.setSize({ width: this.width(), height: HEIGHT });
  }

  redraw() {
    for (const { plot } of this.plots) plot.redraw(false, false);
  }
}
