// geofeas review: keyboard decisions, the time slider and live updates. No external code.
(function () {
  "use strict";
  const csrf = document.querySelector('meta[name="csrf-token"]').content;
  const stateEl = document.getElementById("state");
  const state = stateEl ? JSON.parse(stateEl.textContent) : {};
  const msg = document.getElementById("message");
  const opInput = document.getElementById("operator");
  const saved = window.localStorage.getItem("geofeas-operator");
  if (saved && opInput) opInput.value = saved;
  if (opInput) opInput.addEventListener("change", () => {
    window.localStorage.setItem("geofeas-operator", opInput.value.trim());
  });

  function show(text, kind) {
    msg.textContent = text;
    msg.className = kind || "";
    msg.hidden = false;
  }

  async function post(url, body) {
    const r = await fetch(url, {
      method: "POST",
      headers: { "Content-Type": "application/json", "X-CSRF-Token": csrf },
      body: JSON.stringify(body),
    });
    let data = {};
    try { data = await r.json(); } catch (e) { data = { error: "bad response " + r.status }; }
    return { status: r.status, data: data };
  }

  async function decide(action) {
    if (state.page !== "pair") return;
    const operator = opInput.value.trim();
    if (action === "undo") {
      const r = await post("/api/undo", { operator: operator });
      if (r.status === 200) {
        show("Undone: " + r.data.message, "ok");
        window.setTimeout(() => { window.location.href = r.data.pair; }, 600);
      } else {
        show(r.data.error, r.status === 409 ? "conflict" : "error");
      }
      return;
    }
    const r = await post("/api/decide", {
      track_a: state.a, track_b: state.b, decision: action,
      operator: operator, seen: state.seen, p_same: state.p_same,
    });
    if (r.status === 200) {
      show("Saved: " + r.data.message, "ok");
      window.setTimeout(() => { window.location.href = r.data.next; }, 600);
    } else {
      show(r.data.error, r.status === 409 ? "conflict" : "error");
    }
  }

  document.querySelectorAll("button[data-action]").forEach((b) => {
    b.addEventListener("click", () => decide(b.dataset.action));
  });
  const keys = { s: "same", d: "different", k: "skip", u: "undo" };
  document.addEventListener("keydown", (ev) => {
    const t = ev.target;
    if (t && (t.tagName === "INPUT" && t.type !== "range" || t.tagName === "SELECT" ||
              t.tagName === "TEXTAREA")) return;
    if (ev.ctrlKey || ev.metaKey || ev.altKey) return;
    const action = keys[ev.key];
    if (action) { ev.preventDefault(); decide(action); }
  });

  // the instant under the slider
  const slider = document.getElementById("slider");
  function place(el, e) {
    el.setAttribute("cx", e[0]); el.setAttribute("cy", e[1]);
    el.setAttribute("rx", e[2]); el.setAttribute("ry", e[3]);
    el.setAttribute("transform", "rotate(" + e[4] + " " + e[0] + " " + e[1] + ")");
  }
  function moveTo(k) {
    const p = state.payload;
    if (!p || !p.t.length) return;
    place(document.getElementById("now-a"), p.a[k]);
    place(document.getElementById("now-b"), p.b[k]);
    const c = document.getElementById("cursor");
    c.setAttribute("x1", p.cursor[k]); c.setAttribute("x2", p.cursor[k]);
    document.getElementById("instant").textContent =
      "t = " + p.t[k] + " s: " + p.sigma[k] + " standard errors apart";
  }
  if (slider) {
    slider.addEventListener("input", () => moveTo(parseInt(slider.value, 10)));
    moveTo(parseInt(slider.value, 10));
  }

  // live updates: the station re-associates in the background
  const status = document.getElementById("status");
  async function poll() {
    try {
      const r = await fetch("/api/state", { cache: "no-store" });
      const s = await r.json();
      status.textContent = (s.computing ? "re-associating... " : "") +
        s.decided + " decided, " + s.remaining + " remaining";
      if (s.error) show("The last re-association failed: " + s.error, "error");
      if (state.page === "queue" && s.version !== state.version && !s.computing) {
        window.location.reload();
      }
      if (state.page === "pair" && s.version !== state.version && !s.computing) {
        const q = new URLSearchParams({ a: state.a, b: state.b });
        const p = await (await fetch("/api/pair?" + q, { cache: "no-store" })).json();
        if (p.p_same !== undefined) {
          document.getElementById("p-same").textContent = (100 * p.p_same).toFixed(1) + " %";
          state.p_same = p.p_same;
          state.version = p.version;
        }
      }
    } catch (e) {
      status.textContent = "station unreachable";
    }
  }
  poll();
  window.setInterval(poll, 1500);
})();
