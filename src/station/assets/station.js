// The operator station's page: follows the station's view over server-sent events (the
// whole view on connecting, then each change), and sends only what the operator does —
// start a recipe by its number, answer the open question, press Stop — as POST requests
// with the station's token in a header. Text from the station is shown as text, never as
// markup. Plots keep at most as many points as the station does (it halves them as the
// run grows), so the page's memory stays bounded however long the run.
"use strict";

const TOKEN = document.querySelector('meta[name="drivescript-token"]').content;
const $ = (id) => document.getElementById(id);
let view = null;
let receivedAt = performance.now();
let resultSeenFor = null;
const plots = new Map();

function post(path, body) {
  return fetch(path, {
    method: "POST",
    headers: { "content-type": "application/json", "x-drivescript-token": TOKEN },
    body: JSON.stringify(body || {}),
  }).then(async (r) => {
    const text = await r.text();
    let data = {};
    try { data = JSON.parse(text); } catch (_) { data = { error: text || r.statusText }; }
    if (!r.ok) throw new Error(data.error || r.statusText);
    return data;
  });
}

function connect() {
  const events = new EventSource("events");
  events.addEventListener("view", (e) => {
    view = JSON.parse(e.data);
    receivedAt = performance.now();
    plots.forEach((p) => p.el.remove());
    plots.clear();
    render();
  });
  events.onmessage = (e) => {
    if (!view) return;
    apply(JSON.parse(e.data));
    render();
  };
  events.onopen = () => { $("link").textContent = "live"; $("link").classList.add("live"); };
  events.onerror = () => { $("link").textContent = "reconnecting…"; $("link").classList.remove("live"); };
}

function halve(a) { return a.filter((_, i) => i % 2 === 0); }

function apply(ev) {
  const run = view.run;
  switch (ev.kind) {
    case "run":
      view.run = ev.run;
      plots.forEach((p) => p.el.remove());
      plots.clear();
      receivedAt = performance.now();
      break;
    case "step": {
      if (!run) return;
      const steps = run.steps;
      if (ev.step.state === "running") {
        steps.push(ev.step);
        if (steps.length > 200) { steps.shift(); run.earlier_steps++; }
      } else {
        let i = steps.length - 1;
        while (i >= 0 && steps[i].number !== ev.step.number) i--;
        if (i >= 0) steps[i].state = ev.step.state; else steps.push(ev.step);
      }
      if (ev.dialog_closed) run.dialog = null;
      if (ev.elapsed_s !== undefined) setElapsed(ev.elapsed_s);
      break;
    }
    case "progress": if (run) setElapsed(ev.elapsed_s); break;
    case "dialog": if (run) run.dialog = ev.dialog; break;
    case "note": if (run) run.note = ev.text; break;
    case "stops": if (run) run.stops = ev.stops; break;
    case "result": if (run) { run.result = ev.result; run.dialog = null; } loadRuns(); break;
    case "closing": view.closing = true; break;
    case "points":
      if (!run) return;
      ev.series.forEach((s, i) => {
        let mine = run.series[i];
        if (!mine) { mine = { name: s.name, unit: s.unit, t: [], v: [], stride: s.stride }; run.series[i] = mine; }
        while (mine.stride < s.stride) { mine.t = halve(mine.t); mine.v = halve(mine.v); mine.stride *= 2; }
        mine.t.push(...s.t);
        mine.v.push(...s.v);
      });
      setElapsed(ev.elapsed_s);
      break;
  }
}

// The time shown never runs backwards: the page counts on between events, and the run's
// clock in the next event may lag what it has counted.
function shownElapsed() {
  const run = view.run;
  return run.result ? run.elapsed_s : run.elapsed_s + (performance.now() - receivedAt) / 1000;
}

function setElapsed(s) {
  if (!view.run) return;
  view.run.elapsed_s = Math.max(s, shownElapsed());
  receivedAt = performance.now();
}

function clock(seconds) {
  seconds = Math.max(0, Math.round(seconds));
  const h = Math.floor(seconds / 3600), m = Math.floor(seconds / 60) % 60, s = seconds % 60;
  const two = (n) => String(n).padStart(2, "0");
  return h > 0 ? `${h}:${two(m)}:${two(s)}` : `${m}:${two(s)}`;
}

function render() {
  if (!view) return;
  const run = view.run;
  const running = run && !run.result;
  const appears = $("start").hidden && !running;
  $("start").hidden = running;
  // Ready for the scanner: it types the serial where the focus is, then Enter.
  if (appears) $("serial").focus();
  $("run").hidden = !run;
  renderRecipes();
  $("start-button").disabled = view.closing;
  if (view.closing) $("notice").textContent = "The station is shutting down: no new run starts.";
  if (run) renderRun(run);
  renderResult(run);
  renderDialog(running ? run.dialog : null);
}

function renderRecipes() {
  const box = $("recipes");
  if (box.querySelectorAll("input").length === view.recipes.length) return;
  view.recipes.forEach((r, i) => {
    const label = document.createElement("label");
    const input = document.createElement("input");
    input.type = "radio"; input.name = "recipe"; input.value = String(i);
    input.checked = i === 0;
    label.append(input, " " + r.name);
    label.title = r.file + (r.planned_s ? ` (about ${clock(r.planned_s)})` : "");
    box.append(label);
  });
}

function renderRun(run) {
  $("run-title").textContent = `${run.recipe} — unit ${run.serial} — ${run.operator}`;
  const stop = $("stop-button");
  stop.hidden = !!run.result;
  stop.classList.toggle("again", run.stops > 0);
  stop.textContent = run.stops > 0 ? "Power off" : "Stop";
  $("stop-note").textContent = run.result ? "" : run.stops === 1
    ? "Stopping safely: braking to standstill. Press again to switch the power stage off at once."
    : run.stops > 1 ? "Switching the power stage off." : "";
  $("run-note").textContent = run.note || "";
  const list = $("steps");
  list.replaceChildren(...run.steps.map((s) => {
    const li = document.createElement("li");
    li.className = s.state;
    const state = document.createElement("span"); state.className = "state";
    state.textContent = { running: "running", ok: "ok", fail: "FAIL", marginal: "marginal" }[s.state] || s.state;
    const number = document.createElement("span"); number.className = "number"; number.textContent = s.number;
    const label = document.createElement("span"); label.textContent = s.label;
    li.append(state, number, label);
    return li;
  }));
  const last = list.lastElementChild;
  if (last && !run.result) last.scrollIntoView({ block: "nearest" });
  renderPlots(run);
  tick();
}

function tick() {
  const run = view && view.run;
  if (!run) return;
  const elapsed = shownElapsed();
  $("elapsed").textContent = `elapsed ${clock(elapsed)}`;
  $("remaining").textContent = run.planned_s && !run.result
    ? `· about ${clock(Math.max(0, run.planned_s - elapsed))} left` : "";
}

function renderPlots(run) {
  const box = $("plots");
  const width = Math.max(240, box.clientWidth || 480);
  run.series.forEach((s) => {
    let p = plots.get(s.name);
    if (!p) {
      const el = document.createElement("div");
      const title = document.createElement("div");
      title.className = "plot-title";
      title.textContent = s.unit ? `${s.name} (${s.unit})` : s.name;
      el.append(title);
      box.append(el);
      const chart = new uPlot({
        width, height: 160,
        scales: { x: { time: false } },
        axes: [{ label: "s" }, {}],
        legend: { show: false },
        series: [{}, { label: s.name, stroke: "#2563eb", width: 2 }],
      }, [s.t, s.v], el);
      p = { el, chart, shown: -1 };
      plots.set(s.name, p);
    }
    if (p.shown !== s.t.length || p.stride !== s.stride) {
      p.chart.setData([s.t, s.v]);
      p.shown = s.t.length;
      p.stride = s.stride;
    }
    if (Math.abs(p.chart.width - width) > 8) p.chart.setSize({ width, height: 160 });
  });
}

function renderResult(run) {
  const box = $("result");
  const r = run && run.result;
  box.hidden = !r;
  if (!r) return;
  const word = $("word");
  word.textContent = r.word;
  word.className = "word " + r.word.replace(" ", "-");
  $("verdict-line").textContent = `${run.recipe} — unit ${run.serial}: ${r.verdict}` + (r.reason ? ` — ${r.reason}` : "");
  $("failed").replaceChildren(...r.failed.map((f) => { const li = document.createElement("li"); li.textContent = f; return li; }));
  const end = $("end");
  end.textContent = r.end.join(" · ");
  end.classList.toggle("by-hand", r.check_by_hand);
  const links = $("links");
  const items = [];
  if (r.report) { const a = document.createElement("a"); a.href = "report"; a.target = "_blank"; a.textContent = "Run report"; items.push(a); }
  if (r.certificate) { const a = document.createElement("a"); a.href = "certificate"; a.target = "_blank"; a.textContent = "Unit certificate"; items.push(a); }
  links.replaceChildren(...items);
  if (resultSeenFor !== run.id) {
    resultSeenFor = run.id;
    const serial = $("serial");
    serial.value = "";
    serial.focus();
  }
}

let shownDialog = null;
function renderDialog(d) {
  const box = $("dialog");
  box.hidden = !d;
  if (!d) { shownDialog = null; return; }
  const fresh = shownDialog !== d.id;
  shownDialog = d.id;
  $("dialog-step").textContent = `Step ${d.number}`;
  $("dialog-text").textContent = d.text;
  $("dialog-hint").textContent = d.kind === "value" || d.kind === "text" ? d.hint : "";
  $("dialog-error").textContent = d.error ? d.error : d.answered ? "checking…" : "";
  const row = $("dialog-input-row");
  const input = $("dialog-input");
  row.hidden = !(d.kind === "value" || d.kind === "text");
  input.inputMode = d.kind === "value" ? "decimal" : "text";
  $("dialog-unit").textContent = d.unit || "";
  input.disabled = d.answered;
  if (!fresh) {
    [...$("dialog-buttons").children].forEach((b) => (b.disabled = d.answered));
    return;
  }
  input.value = "";
  const button = (text, cls, answer) => {
    const b = document.createElement("button");
    b.type = answer === null ? "submit" : "button";
    b.className = cls; b.textContent = text; b.disabled = d.answered;
    if (answer !== null) b.onclick = () => answerDialog(d.id, answer);
    return b;
  };
  const buttons = {
    instruct: [button("Done", "ok", "")],
    confirm: [button("Yes", "yes", "yes"), button("No", "no", "no")],
    value: [button("OK", "ok", null)],
    text: [button("OK", "ok", null)],
  }[d.kind];
  $("dialog-buttons").replaceChildren(...buttons);
  (row.hidden ? buttons[0] : input).focus();
}

function answerDialog(id, answer) {
  post("api/answer", { dialog: id, answer }).catch((e) => { $("dialog-error").textContent = e.message; });
}

$("dialog-form").addEventListener("submit", (e) => {
  e.preventDefault();
  const d = view && view.run && view.run.dialog;
  if (d && !d.answered && (d.kind === "value" || d.kind === "text")) answerDialog(d.id, $("dialog-input").value);
});

function startRun(recipe, serial, operator) {
  $("notice").textContent = "";
  localStorage.setItem("drivescript-operator", operator);
  return post("api/start", { recipe, serial, operator }).catch((e) => { $("notice").textContent = e.message; });
}

$("start-form").addEventListener("submit", (e) => {
  e.preventDefault();
  const chosen = document.querySelector('input[name="recipe"]:checked');
  startRun(chosen ? Number(chosen.value) : 0, $("serial").value, $("operator").value);
});

// Stop is at hand while a question waits too: the dialog covers the page's own button.
const pressStop = () => post("api/stop").catch((e) => { $("stop-note").textContent = e.message; });
$("stop-button").addEventListener("click", pressStop);
$("dialog-stop").addEventListener("click", pressStop);

function loadRuns() {
  fetch("api/runs").then((r) => r.json()).then((data) => {
    const rows = (data.runs || []).map((r) => {
      const tr = document.createElement("tr");
      [r.started, r.serial, r.recipe, r.operator, r.verdict].forEach((text, i) => {
        const td = document.createElement("td");
        td.textContent = text || "";
        if (i === 4) td.className = text;
        tr.append(td);
      });
      return tr;
    });
    if (data.error) {
      const tr = document.createElement("tr");
      const td = document.createElement("td");
      td.colSpan = 5; td.textContent = data.error;
      tr.append(td);
      rows.push(tr);
    }
    $("runs").replaceChildren(...rows);
  }).catch(() => {});
}

$("operator").value = localStorage.getItem("drivescript-operator") || "";
$("operator").addEventListener("input", () => localStorage.setItem("drivescript-operator", $("operator").value));
setInterval(tick, 500);
// A panel turned or a window resized: the plots take the new width.
window.addEventListener("resize", render);
connect();
loadRuns();
