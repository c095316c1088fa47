// contphy-eval view: the unit browser of a run page.
//
// Reads window.CONTPHY_INDEX (units.js: per unit [id, scenario, family, correct, stage] as
// indices into its name lists), filters it by the state in the URL's hash (scenario, family,
// correct, stage, page, unit), shows a page of rows, and opens a unit's detail from its chunk
// (units/<chunk>.js, loaded with a <script> element: browsers refuse fetch() under file://).
// Text from the run (questions, programs, completions, errors) is set with textContent only.
"use strict";

(function () {
  const PAGE_ROWS = 100;
  const index = window.CONTPHY_INDEX;
  const status = document.getElementById("status");
  if (!index) {
    status.textContent = "units.js is missing: this page must sit in the folder `view` wrote.";
    return;
  }
  const units = index.units;
  const position = new Map();
  units.forEach((unit, i) => position.set(unit[0], i));
  const chunks = new Map();
  const pendingChunks = new Map();

  window.contphyChunk = function (chunk, details) {
    chunks.set(chunk, details);
    const waiting = pendingChunks.get(chunk) || [];
    pendingChunks.delete(chunk);
    waiting.forEach((resolve) => resolve(details));
  };

  function loadChunk(chunk) {
    if (chunks.has(chunk)) return Promise.resolve(chunks.get(chunk));
    return new Promise((resolve, reject) => {
      const waiting = pendingChunks.get(chunk);
      if (waiting) {
        waiting.push(resolve);
        return;
      }
      pendingChunks.set(chunk, [resolve]);
      const script = document.createElement("script");
      script.src = "units/" + chunk + ".js";
      script.onerror = () => reject(new Error("cannot load units/" + chunk + ".js"));
      document.head.appendChild(script);
    });
  }

  function readState() {
    const params = new URLSearchParams(location.hash.slice(1));
    return {
      scenario: params.get("scenario") || "",
      family: params.get("family") || "",
      correct: params.get("correct") || "",
      stage: params.get("stage") || "",
      page: Math.max(1, parseInt(params.get("page") || "1", 10) || 1),
      unit: params.get("unit") || "",
    };
  }

  function writeState(state) {
    const params = new URLSearchParams();
    for (const key of ["scenario", "family", "correct", "stage", "unit"]) {
      if (state[key]) params.set(key, state[key]);
    }
    if (state.page > 1) params.set("page", String(state.page));
    const hash = params.toString();
    if (location.hash.slice(1) !== hash) location.hash = hash;
    else render();
  }

  function element(tag, text, className) {
    const node = document.createElement(tag);
    if (text !== undefined && text !== null) node.textContent = String(text);
    if (className) node.className = className;
    return node;
  }

  function select(name, label, choices, value) {
    const wrapper = element("label", label + " ");
    const box = element("select");
    box.name = name;
    box.id = "filter-" + name;
    for (const [optionValue, optionLabel] of choices) {
      const option = element("option", optionLabel);
      option.value = optionValue;
      if (optionValue === value) option.selected = true;
      box.appendChild(option);
    }
    box.addEventListener("change", () => {
      const state = readState();
      state[name] = box.value;
      state.page = 1;
      state.unit = "";
      writeState(state);
    });
    wrapper.appendChild(box);
    return wrapper;
  }

  function counts(column) {
    const result = new Map();
    for (const unit of units) result.set(unit[column], (result.get(unit[column]) || 0) + 1);
    return result;
  }

  const scenarioCounts = counts(1);
  const familyCounts = counts(2);
  const stageCounts = counts(4);

  function renderFilters(state) {
    const form = document.getElementById("filters");
    form.replaceChildren(
      select("scenario", "Scenario", [["", "all"]].concat(index.scenarios.map((name, i) =>
        [name, name + " (" + (scenarioCounts.get(i) || 0) + ")"])), state.scenario),
      select("family", "Family", [["", "all"]].concat(index.families.map((name, i) =>
        [name, name + " (" + (familyCounts.get(i) || 0) + ")"])), state.family),
      select("correct", "Correct", [["", "all"], ["1", "correct"], ["0", "wrong"]], state.correct),
      select("stage", "Failed stage", [["", "any"], ["none", "none (answered)"]].concat(
        index.stages.map((name, i) => [name, name + " (" + (stageCounts.get(i) || 0) + ")"])),
        state.stage),
    );
  }

  function filtered(state) {
    const scenario = state.scenario ? index.scenarios.indexOf(state.scenario) : -2;
    const family = state.family ? index.families.indexOf(state.family) : -2;
    const stage = state.stage === "none" ? -1 : state.stage ? index.stages.indexOf(state.stage) : -2;
    const correct = state.correct === "" ? -1 : state.correct === "1" ? 1 : 0;
    const kept = [];
    for (let i = 0; i < units.length; i++) {
      const unit = units[i];
      if (scenario !== -2 && unit[1] !== scenario) continue;
      if (family !== -2 && unit[2] !== family) continue;
      if (stage !== -2 && unit[4] !== stage) continue;
      if (correct !== -1 && unit[3] !== correct) continue;
      kept.push(i);
    }
    return kept;
  }

  function renderTable(state, kept) {
    const pages = Math.max(1, Math.ceil(kept.length / PAGE_ROWS));
    const page = Math.min(state.page, pages);
    const body = document.querySelector("#units tbody");
    const rows = [];
    for (const i of kept.slice((page - 1) * PAGE_ROWS, page * PAGE_ROWS)) {
      const unit = units[i];
      const row = element("tr");
      row.dataset.unit = unit[0];
      row.appendChild(element("td", unit[0]));
      row.appendChild(element("td", index.scenarios[unit[1]]));
      row.appendChild(element("td", index.families[unit[2]]));
      row.appendChild(element("td", unit[3] ? "yes" : "no", unit[3] ? "yes" : "no"));
      row.appendChild(element("td", unit[4] < 0 ? "" : index.stages[unit[4]]));
      row.addEventListener("click", () => {
        const next = readState();
        next.unit = unit[0];
        writeState(next);
      });
      rows.push(row);
    }
    body.replaceChildren(...rows);
    const pager = document.getElementById("pager");
    const previous = element("button", "previous");
    previous.type = "button";
    previous.disabled = page <= 1;
    previous.addEventListener("click", () => { const s = readState(); s.page = page - 1; writeState(s); });
    const next = element("button", "next");
    next.type = "button";
    next.disabled = page >= pages;
    next.addEventListener("click", () => { const s = readState(); s.page = page + 1; writeState(s); });
    pager.replaceChildren(previous, element("span", "page " + page + " of " + pages, "page"), next);
  }

  function field(table, label, value) {
    if (value === undefined || value === null || value === "") return;
    const row = element("tr");
    row.appendChild(element("th", label));
    const cell = element("td");
    if (value instanceof Node) cell.appendChild(value);
    else cell.textContent = typeof value === "string" ? value : JSON.stringify(value);
    row.appendChild(cell);
    table.appendChild(row);
  }

  function programBlock(program, hash, title) {
    const block = element("div", null, "program");
    block.appendChild(element("h3", title));
    if (!program) {
      block.appendChild(element("p", hash
        ? "Program " + hash.slice(0, 16) + "…: its text is not in the program cache given to `view` (--cache)."
        : "No program was obtained."));
      return block;
    }
    block.appendChild(element("p", "source: " + program.source + (hash ? ", program " + hash.slice(0, 16) + "…" : "")));
    block.appendChild(element("pre", program.text, "source"));
    if (program.completion) {
      const details = element("details");
      details.appendChild(element("summary", "LLM completion"));
      details.appendChild(element("pre", program.completion, "completion"));
      block.appendChild(details);
    }
    return block;
  }

  // The frames perception read for the unit's video, its detections drawn on them and listed
  // beside each in the colour of their outline.
  function framesBlock(detail, frames) {
    const block = element("div", null, "frames");
    block.appendChild(element("h3", "What the detector saw"));
    const decoded = detail.work ? detail.work.frames_decoded : 0;
    block.appendChild(element("p", "Every tenth frame perception read of video " + detail.video +
      " (frames " + frames.map((f) => f.frame).join(", ") + "), by any unit of the run; this " +
      "unit's scene decoded " + decoded + " frame(s) itself (0: an earlier unit read the video)."));
    for (const frame of frames) {
      const figure = element("figure", null, "frame");
      const image = element("img");
      image.src = "frames/" + detail.scenario + "/" + detail.video + "/" + frame.image;
      image.alt = "frame " + frame.frame + " with the detector's boxes and masks";
      figure.appendChild(image);
      const caption = element("figcaption", "frame " + frame.frame);
      const list = element("ul", null, "detections");
      for (const found of frame.detections) {
        const item = element("li", found.class + (found.color ? " (" + found.color + ")" : "") +
          ", score " + found.score + ", box " + found.box.join(", "));
        if (/^#[0-9a-f]{6}$/.test(found.outline)) item.style.borderLeft = "0.6em solid " + found.outline;
        list.appendChild(item);
      }
      caption.appendChild(list);
      figure.appendChild(caption);
      block.appendChild(figure);
    }
    return block;
  }

  function renderDetail(detail) {
    const section = document.getElementById("detail");
    section.hidden = false;
    const close = element("button", "close");
    close.type = "button";
    close.addEventListener("click", () => { const s = readState(); s.unit = ""; writeState(s); });
    const table = element("table", null, "facts");
    field(table, "unit", detail.unit);
    field(table, "video", detail.scenario + " " + detail.video);
    field(table, "family", detail.family);
    field(table, "question", detail.question);
    if (detail.options && detail.options.length) {
      const list = element("ol", null, "options");
      for (const option of detail.options) {
        const item = element("li", option.letter + ". " + option.text + (option.correct ? "  (true)" : "  (false)"));
        if (option.letter === detail.option) item.className = "this-option";
        list.appendChild(item);
      }
      field(table, "options", list);
    }
    field(table, "option", detail.option);
    field(table, "truth", detail.truth);
    field(table, "answer", detail.answer);
    field(table, "value", detail.value === undefined || detail.value === null ? undefined : JSON.stringify(detail.value));
    field(table, "correct", detail.correct ? "yes" : "no");
    if (detail.error) {
      field(table, "error", detail.error.stage + " / " + detail.error.kind + ": " + detail.error.message);
    }
    field(table, "program origin", detail.origin);
    if (detail.votes && detail.votes.length) field(table, "votes", detail.votes.map((v) => v[0] + " × " + v[1]).join(", "));
    if (detail.work) field(table, "work", Object.entries(detail.work).map(([k, v]) => k + " " + v).join(", "));
    if (detail.usage) {
      const usage = detail.usage;
      field(table, "usage", usage.prompt_tokens + " prompt + " + usage.completion_tokens + " completion tokens" +
        (usage.cost_usd === null || usage.cost_usd === undefined ? "" : ", $" + usage.cost_usd.toFixed(4)) +
        ", " + usage.requests + " requests");
    }
    if (detail.timing_ms) field(table, "time (ms)", "own " + detail.timing_ms.own + ", scene API " + detail.timing_ms.api + ", wall " + detail.timing_ms.wall);
    const parts = [close, element("h2", "Unit " + detail.unit), table];
    const frames = (window.CONTPHY_FRAMES || {})[detail.scenario + "/" + detail.video];
    if (frames && frames.length) parts.push(framesBlock(detail, frames));
    if (detail.origin !== undefined) parts.push(programBlock(detail.program, detail.program_hash, "Program"));
    (detail.attempts || []).forEach((attempt) => {
      const title = "Attempt: sample " + attempt.sample + ", turn " + attempt.attempt +
        (attempt.error ? " (failed: " + attempt.error.stage + " / " + attempt.error.kind + ": " + attempt.error.message + ")" : "");
      parts.push(programBlock(attempt.program, attempt.program_hash, title));
    });
    section.replaceChildren(...parts);
    // Since the navigation began: what opening this unit from its link costs (bench view).
    section.dataset.detailMs = performance.now().toFixed(1);
    section.scrollIntoView({ block: "start" });
  }

  function renderUnit(state) {
    const section = document.getElementById("detail");
    if (!state.unit) {
      section.hidden = true;
      section.replaceChildren();
      return;
    }
    const at = position.get(state.unit);
    if (at === undefined) {
      section.hidden = false;
      section.replaceChildren(element("p", "No unit " + state.unit + " in this run."));
      return;
    }
    const chunk = Math.floor(at / index.chunk_units);
    loadChunk(chunk).then((details) => {
      if (readState().unit !== state.unit) return;
      renderDetail(details[at - chunk * index.chunk_units]);
    }, (error) => {
      section.hidden = false;
      section.replaceChildren(element("p", error.message));
    });
  }

  function render() {
    const state = readState();
    renderFilters(state);
    const filterStart = performance.now();
    const kept = filtered(state);
    const filterMs = performance.now() - filterStart;
    renderTable(state, kept);
    renderUnit(state);
    const correct = kept.reduce((sum, i) => sum + units[i][3], 0);
    status.textContent = kept.length + " of " + units.length + " units shown, " + correct + " correct";
    status.dataset.filterMs = filterMs.toFixed(1);
    // Since the navigation began: parsing units.js, this script, and this render.
    status.dataset.loadMs = performance.now().toFixed(1);
    status.dataset.shown = String(kept.length);
  }

  window.addEventListener("hashchange", render);
  render();
})();
