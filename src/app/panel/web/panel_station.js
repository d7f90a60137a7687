// The station's side of the operator panel (issue 26 §1), beside panel.js, which calls it at four
// points (Station.onState, Station.startBody, Station.afterStart, Station.onEvent):
//   - the operator: entered or scanned once per shift, kept in this browser until changed,
//     required before Start and sent with it;
//   - a fixture: one serial field per fitted position (scan, Enter moves to the next; a position
//     left empty is ticked "leave empty", never just forgotten), each unit's state, runs, outcome
//     and report;
//   - the plan: warm-up (with its own progress), each run (Ω, wave state, length), the estimate,
//     every limit and fit check, each with its status, before Start and during the run;
//   - a session without limits is "not judged", never a green PASS;
//   - after an Abort, the table's rate until it reads zero, and the page says so.
"use strict";

const Station = (() => {
  const byId = (id) => document.getElementById(id);
  const kOperatorKey = "hrgbench.operator";
  const kZeroRateRadS = 1e-3;  // the table "reads zero" below this (its stable tolerance)
  let catalog = null;          // the last /api/state
  let session = null;          // the shown session: {limits, sequence, fixture, units}
  let runCount = 0;

  function cell(row, value, cls) {
    const c = row.insertCell();
    c.textContent = value;
    if (cls) c.className = cls;
    return c;
  }
  function num(x, digits) { return x === null || x === undefined ? "—" : Number(x).toFixed(digits); }
  function general(x) { return x === null || x === undefined ? "—" : Number(x).toPrecision(4); }

  // ---- the operator ----
  const operatorField = byId("operator");
  operatorField.value = localStorage.getItem(kOperatorKey) || "";
  operatorField.addEventListener("change", () => {
    localStorage.setItem(kOperatorKey, operatorField.value.trim());
  });
  operatorField.addEventListener("keydown", (ev) => {
    if (ev.key !== "Enter") return;
    localStorage.setItem(kOperatorKey, operatorField.value.trim());
    const next = catalog && catalog.positions.length > 0 ?
      byId("serial-" + catalog.positions[0]) : byId("serial");
    if (next) next.focus();
  });

  // ---- a fixture's serial fields ----
  function positionsShown() { return catalog !== null && catalog.positions.length > 0; }
  function buildPositions(positions) {
    const box = byId("fixture-serials");
    if (box.dataset.built === "true") return;
    box.dataset.built = "true";
    box.hidden = false;
    byId("serial").hidden = true;
    byId("serial-label").textContent = "Unit serials";
    positions.forEach((position, i) => {
      const row = document.createElement("div");
      row.className = "position-row";
      row.dataset.position = position;
      const label = document.createElement("label");
      label.htmlFor = "serial-" + position;
      label.textContent = "Position " + position;
      const input = document.createElement("input");
      input.id = "serial-" + position;
      input.dataset.position = position;
      input.autocomplete = "off";
      input.placeholder = "scan or type";
      const empty = document.createElement("input");
      empty.type = "checkbox";
      empty.id = "empty-" + position;
      const emptyLabel = document.createElement("label");
      emptyLabel.htmlFor = empty.id;
      emptyLabel.textContent = "leave empty";
      empty.addEventListener("change", () => {
        input.disabled = empty.checked;
        if (empty.checked) input.value = "";
      });
      // The scanner's flow: a scan ends with Enter, which moves to the next position to fill.
      input.addEventListener("keydown", (ev) => {
        if (ev.key !== "Enter") return;
        ev.preventDefault();
        if (input.value.trim() === "") {
          message("position " + position + ": scan a serial or tick \"leave empty\"");
          return;
        }
        for (let k = i + 1; k < positions.length; ++k) {
          const next = byId("serial-" + positions[k]);
          if (!next.disabled) { next.focus(); return; }
        }
        byId("start").focus();
      });
      row.append(label, input, empty, emptyLabel);
      box.appendChild(row);
    });
  }

  // The start request's unit part and the operator, or {error}.
  function startBody() {
    const operator = operatorField.value.trim();
    if (operator === "") return { error: "enter or scan your operator id first (once per shift)" };
    localStorage.setItem(kOperatorKey, operator);
    if (!positionsShown()) return { serial: byId("serial").value, operator };
    const serials = {};
    for (const position of catalog.positions) {
      const value = byId("serial-" + position).value.trim();
      if (value === "" && !byId("empty-" + position).checked)
        return { error: "position " + position + ": scan a serial or tick \"leave empty\"" };
      serials[position] = value;
    }
    return { serials, operator };
  }
  function afterStart() {
    if (!positionsShown()) return;
    for (const position of catalog.positions) byId("serial-" + position).value = "";
    byId("serial-" + catalog.positions[0]).focus();
  }

  // ---- the plan ----
  function planRow(step, what, status) {
    const row = byId("plan").tBodies[0].insertRow();
    row.dataset.step = step;
    cell(row, step);
    cell(row, what);
    const s = cell(row, status || "planned");
    s.className = "status";
    row.dataset.status = status || "planned";
    return row;
  }
  function setStep(step, status, note) {
    const row = byId("plan").querySelector('tr[data-step="' + CSS.escape(step) + '"]');
    if (!row) return;
    row.dataset.status = status;
    row.cells[2].textContent = status + (note ? " · " + note : "");
  }
  function renderPlan(sequence, limits, title) {
    byId("plan").tBodies[0].innerHTML = "";
    byId("plan-title").textContent = title;
    byId("warmup-bar").style.width = "0";
    byId("warmup-text").textContent = "";
    if (!sequence) return;
    const p = sequence.plan;
    // The operator's steps where they come: before the warm-up, before a run, at the end.
    const prompts = (where, run) => (p.prompts || [])
      .filter((q) => q.at === where && (where !== "before_run" || q.run === run))
      .forEach((q) => planRow("prompt " + q.id, "operator: " + q.text));
    prompts("start");
    planRow("warm-up", "at least " + num(p.warmup.min_s, 0) + " s, then until the temperature " +
            "drifts ≤ " + p.warmup.max_drift_c + " °C over " + num(p.warmup.window_s, 0) +
            " s (gives up after " + num(p.warmup.timeout_s, 0) + " s)");
    runCount = p.runs.length;
    p.runs.forEach((r, i) => {
      prompts("before_run", i + 1);
      planRow("run " + (i + 1), "Ω " + num(r.omega_rad_s, 4) + " rad/s; wave a " + r.a + ", b " +
              r.b + ", θ " + num(r.theta_rad, 3) + " rad; " + r.free_run_s + " s at " +
              r.sample_rate_hz + " Hz");
    });
    prompts("end");
    planRow("estimate", "maximum likelihood over every run");
    if (!limits) {
      planRow("limits", "none: the session is not judged against the unit's limits", "not judged");
      return;
    }
    for (const l of limits.plan.limits)
      planRow("limit " + l.quantity, general(l.min) + " … " + general(l.max));
    for (let run = 1; run <= p.runs.length; ++run)
      for (const name of limits.plan.fit_checks)
        planRow("fit " + run + " " + name, "run " + run + ": " + name.replace(/_/g, " "));
  }
  function previewPlan() {
    if (!catalog || (session && session.live)) return;
    const seq = catalog.sequences[Number(byId("sequence").value)];
    const lim = byId("limits").value === "" ? null : catalog.limits[Number(byId("limits").value)];
    renderPlan(seq, lim, "before Start: " + (seq ? seq.name : "") + (lim ? " · limits " +
               lim.name : " · no limits"));
  }
  byId("sequence").addEventListener("change", previewPlan);
  byId("limits").addEventListener("change", previewPlan);

  function onState(s) {
    catalog = s;
    if (s.positions.length > 0) buildPositions(s.positions);
    if (session === null) previewPlan();  // a session shown keeps its plan and statuses
  }

  // ---- a fixture's units ----
  function unitRow(position) {
    return byId("units").querySelector('tr[data-position="' + CSS.escape(position) + '"]');
  }
  function showUnits(units) {
    byId("units-box").hidden = false;
    const body = byId("units").tBodies[0];
    body.innerHTML = "";
    for (const u of units) {
      const row = body.insertRow();
      row.dataset.position = u.position;
      row.dataset.folder = u.session;
      row.dataset.runs = "0";
      cell(row, u.position);
      cell(row, u.serial);
      cell(row, "waiting").className = "state";
      cell(row, "0 / " + runCount);
      cell(row, "—").className = "outcome";
      cell(row, "");
    }
  }
  function unitsPhase(e) {
    for (const row of byId("units").tBodies[0].rows) {
      if (row.dataset.ended === "true" || row.dataset.decided === "true") continue;
      row.cells[2].textContent = e.run > 0 ? "run " + e.run_id + ": " + e.phase : e.phase;
      row.dataset.state = e.phase;
    }
  }

  // ---- events ----
  function onEvent(e) {
    switch (e.type) {
      case "panel_session": {
        session = { live: true, limits: e.limits, sequence: e.sequence, fixture: false };
        byId("operator-shown").textContent = e.operator ? "· operator " + e.operator : "";
        byId("table-stop").hidden = true;
        byId("units-box").hidden = true;
        const seq = catalog && catalog.sequences.find((q) => q.name === e.sequence);
        const lim = catalog && e.limits ? catalog.limits.find((q) => q.name === e.limits) : null;
        renderPlan(seq, lim, e.session + " · " + e.sequence +
                   (e.limits ? " · limits " + e.limits : " · no limits"));
        if (e.units && e.units.length > 0) {
          session.fixture = true;
          showUnits(e.units.map((u) => ({ position: u.position, serial: u.serial,
                                          session: u.position + "-" + u.serial })));
        }
        break;
      }
      case "fixture_started":
        session.fixture = true;
        showUnits(e.units);
        break;
      case "phase":
      case "progress":
        if (e.phase === "warm-up") {
          setStep("warm-up", "running");
          if (e.type === "progress") warmupProgress(e);
        } else if (e.phase === "estimate") {
          setStep("warm-up", "done");
          setStep("estimate", "running");
        } else if (e.phase === "stopping") {
          tableStopping(e);
        } else if (e.phase === "prompt") {
          // The prompt's own row says it is open (its event); the run it precedes has not begun.
        } else if (e.run_id > 0) {
          setStep("warm-up", "done");
          byId("warmup-bar").style.width = "100%";
          const row = byId("plan").querySelector('tr[data-step="run ' + e.run_id + '"]');
          if (row && (row.dataset.status === "planned" || row.dataset.status === "running"))
            setStep("run " + e.run_id, "running", e.phase);
        }
        if (session && session.fixture && e.type === "phase") unitsPhase(e);
        break;
      case "run_result":
        setStep("run " + e.run_id, e.status, e.samples + " samples");
        break;
      case "prompt":
        setStep("prompt " + e.id, "open", "waiting for the operator (the table at zero)");
        break;
      case "prompt_answered":
        setStep("prompt " + e.id, e.answer === "confirm" ? "confirmed" : "aborted",
                (e.by ? "by " + e.by : "") + (e.how === "auto" ? " (auto)" : ""));
        break;
      case "unit_run_result": {
        setStep("run " + e.run_id, e.status);
        const row = unitRow(e.position);
        if (row) {
          row.dataset.runs = String(Number(row.dataset.runs) + (e.status === "complete" ? 1 : 0));
          row.cells[3].textContent = row.dataset.runs + " / " + runCount;
        }
        break;
      }
      case "estimate":
        setStep("estimate", "done");
        break;
      case "limit":
        setStep("limit " + e.quantity, e.status, general(e.value) + " ± " + general(e.std));
        break;
      case "fit_check":
        setStep("fit " + e.run + " " + e.name, e.status, general(e.value) + " (max " +
                general(e.max) + ")");
        break;
      case "decided": {
        // The sequence's [adaptive]: this unit's verdict can no longer change; it takes no
        // further run (decided within a run: its capture stops there). The runs after it are not
        // needed once no unit on the table needs them.
        const when = typeof e.within_run_s === "number"
          ? general(e.within_run_s) + " s into run " + e.after_run
          : "after run " + e.after_run;
        const note = "decided " + when + " of " + e.planned_runs + ": " + e.why;
        if (session && session.fixture) {
          const row = unitRow(e.position);
          if (row) {
            row.dataset.decided = "true";
            row.cells[2].textContent = note;
          }
        }
        const units = session && session.fixture ? byId("units").tBodies[0].rows : [];
        const waiting = Array.from(units).some((r) => r.dataset.decided !== "true" &&
                                                      r.dataset.ended !== "true");
        if (!waiting) {
          for (let run = e.after_run + 1; run <= e.planned_runs; ++run) {
            const row = byId("plan").querySelector('tr[data-step="run ' + run + '"]');
            if (row && row.dataset.status === "planned") setStep("run " + run, "not needed", note);
          }
        }
        break;
      }
      case "unit_outcome": {
        const row = unitRow(e.position);
        if (!row) break;
        row.dataset.ended = "true";
        row.cells[2].textContent = "ended";
        const judged = session && session.limits;
        const kind = e.outcome === "PASS" && !judged ? "NOT-JUDGED" : e.outcome;
        row.cells[4].textContent = kind === "NOT-JUDGED" ? "not judged" : e.outcome;
        row.cells[4].className = "outcome " + kind;
        row.cells[4].title = e.reason;
        row.dataset.outcome = kind;
        if (e.report) {
          const a = document.createElement("a");
          a.href = withToken("sessions/" + encodeURIComponent(state.session) + "/" +
                             encodeURIComponent(row.dataset.folder) + "/report/report.html");
          a.textContent = "report";
          row.cells[5].replaceChildren(a);
        }
        break;
      }
      case "outcome":
        if (session) session.live = false;
        // Nothing judged (no limits): the fit may be fine, the unit is not shown as passed.
        if (e.outcome === "PASS" && session && !session.limits) {
          byId("outcome").dataset.kind = "NOT-JUDGED";
          byId("outcome").textContent = "not judged";
          byId("outcome-reason").textContent = "no limits were chosen: " + e.reason +
            "; nothing was judged against the unit's limits";
        }
        for (const row of byId("plan").tBodies[0].rows) {
          if (row.dataset.status !== "planned" && row.dataset.status !== "running") continue;
          // A fixture's estimate, limits and fit checks are each unit's: in its row and report.
          const own = row.dataset.step === "estimate" || row.dataset.step.startsWith("limit") ||
                      row.dataset.step.startsWith("fit");
          if (session && session.fixture && own && e.outcome !== "ABORTED")
            setStep(row.dataset.step, "per unit", "see each unit's outcome and report");
          else
            setStep(row.dataset.step, row.dataset.step.startsWith("fit") ? "not checked" :
                    "not reached");
        }
        break;
      case "panel_exit":
        if (session) session.live = false;
        if (e.error) {
          byId("outcome-reason").textContent += ": " + e.error;
          message("the session did not run: " + e.error);
        }
        break;
      default:
        break;
    }
  }

  function warmupProgress(e) {
    const seq = catalog && session && catalog.sequences.find((q) => q.name === session.sequence);
    const span = seq ? Math.max(seq.plan.warmup.min_s, seq.plan.warmup.window_s, 1) : 0;
    if (span > 0)
      byId("warmup-bar").style.width = (100 * Math.min(e.elapsed_s / span, 1)).toFixed(1) + "%";
    byId("warmup-text").textContent = "warm-up: " + num(e.elapsed_s, 0) + " s" +
      (seq ? " (at least " + num(seq.plan.warmup.min_s, 0) + " s, a window of " +
       num(seq.plan.warmup.window_s, 0) + " s)" : "");
    byId("warmup-text").dataset.elapsed = String(e.elapsed_s);
  }

  // After an Abort (or any stop), the table's measured rate until it reads zero.
  function tableStopping(e) {
    const box = byId("table-stop");
    box.hidden = false;
    const rate = e.table_rate_rad_s;
    const zero = rate !== null && rate !== undefined && Math.abs(rate) < kZeroRateRadS;
    box.dataset.zero = zero ? "true" : "false";
    box.dataset.rate = String(rate);
    box.textContent = zero ?
      "the table reads zero (" + num(rate, 5) + " rad/s): stopped" :
      "stopping: table commanded to zero, reads " + num(rate, 5) + " rad/s";
    if (rate !== null && rate !== undefined) text("table-rate", num(rate, 5) + " rad/s");
  }

  return { onState, startBody, afterStart, onEvent };
})();
