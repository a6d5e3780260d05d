// Drag flow control for the editors (plain ES module): pointer moves become "drag" messages (or, with
// `message`, any gesture's message: the OutlineEditor's knot drags and handle transforms), at most one in
// flight. Newer positions wait for the kernel's answer and are coalesced to the next animation frame, so
// the kernel never falls behind and the latest position always wins; the final position is always sent
// on release, and the page keeps showing it until the kernel has answered.
//
// With the model's `debug` trait on, every answered move is recorded in
// window.__splinecraft.dragLatencies (pointermove -> path in DOM -> next frame; benchmarks/bench_drag.py).

const ACK_TIMEOUT_MS = 1000; // resend even without an answer after this long (a lost message never blocks)

/** Latency record of move `ackSeq` (its times leave `moveTimes`) once its answer is in the DOM. */
function recordLatency(moveTimes, ackSeq, tArrive, root) {
  const times = moveTimes.get(ackSeq);
  if (!times) return;
  const tDom = performance.now();
  for (const key of moveTimes.keys()) if (key <= ackSeq) moveTimes.delete(key);
  requestAnimationFrame((frameTime) => {
    window.__splinecraft = window.__splinecraft ?? {};
    const log = (window.__splinecraft.dragLatencies = window.__splinecraft.dragLatencies ?? []);
    log.push({
      seq: ackSeq, n: root.dataset.npoints | 0,
      dom: tDom - times.move, frame: performance.now() - times.move, // pointermove -> path in DOM / -> next frame
      wait: times.sent - times.move, kernel: tArrive - times.sent, draw: tDom - tArrive, // the parts
      // frame-aligned: from the start of the animation frame the move came in to the start of the one that
      // paints its answer (a whole number of frame intervals; one interval = painted in the next frame)
      frames: frameTime - times.moveFrame,
    });
    root.dataset.lastDrawnSeq = String(ackSeq);
  });
}

/** Start of the current animation frame (the timestamp its requestAnimationFrame callbacks get). */
const frameStart = () => globalThis.document?.timeline?.currentTime ?? performance.now();

const dragMessage = (drag) => ({ type: "drag", index: drag.index, x: drag.x, y: drag.y });

/**
 * Drag state machine; `onIdle()` is called when a released drag has been answered (redraw the points);
 * `message(drag)` builds the message of a gesture from its fields (seq, gesture and final are added).
 */
export function createDragFlow(model, { onIdle = () => {}, message = dragMessage } = {}) {
  let seq = 0, gesture = 0, inFlight = null, pendingSend = false, rafId = 0;
  let drag = null; // {index, x, y, pointerId, moved, ox, oy; with debug: tMove, tMoveFrame}
  let released = null; // a finished drag whose final position the kernel has not answered yet
  const moveTimes = new Map(); // seq -> {move, sent} (debug only)

  function send(final) {
    seq += 1;
    if (model.get("debug")) moveTimes.set(seq, { move: drag.tMove, moveFrame: drag.tMoveFrame, sent: performance.now() });
    inFlight = { seq, t: performance.now() };
    model.send({ ...message(drag), seq, gesture, final });
  }
  /** Debug only: when the current move came in (page clock and its animation frame's start). */
  function stamp() {
    if (!model.get("debug")) return;
    drag.tMove = performance.now();
    drag.tMoveFrame = frameStart();
  }
  function frame() {
    rafId = 0;
    if (!drag || !pendingSend) return;
    if (inFlight && performance.now() - inFlight.t < ACK_TIMEOUT_MS) return; // wait for the answer
    pendingSend = false;
    send(false);
  }
  const schedule = () => { if (!rafId) rafId = requestAnimationFrame(frame); };

  /** Start a gesture; `fields` stay on it (what `message` reads). */
  function begin(fields, pointerId) {
    gesture += 1;
    drag = { ...fields, pointerId, moved: false };
    stamp();
    return drag;
  }
  /** The gesture moved: take the new `fields`, send them on the next frame. */
  function update(fields) {
    Object.assign(drag, fields);
    drag.moved = true;
    stamp();
    pendingSend = true;
    schedule();
  }

  return {
    begin,
    update,
    /** Start dragging point `index` (at data x, y); `ox, oy`: pointer-to-point offset in screen px. */
    start(index, x, y, pointerId, ox = 0, oy = 0) { return begin({ index, x, y, ox, oy }, pointerId); },
    get active() { return drag; },
    /** The drag to draw (in progress, or released and not yet answered), if it moved. */
    live() {
      const d = drag ?? released;
      return d && d.moved ? d : null;
    },
    move(x, y) { update({ x, y }); },
    /** A one-off final message outside any pointer gesture (an arrow key): a gesture of its own. */
    once(fields) {
      seq += 1;
      gesture += 1;
      model.send({ ...fields, seq, gesture, final: true });
    },
    /** Release: send the final position (if the point moved). */
    end() {
      if (!drag) return;
      if (drag.moved) {
        pendingSend = false;
        send(true);
        drag.finalSeq = seq;
        released = drag;
      }
      drag = null;
    },
    /** The kernel answered move `ackSeq` (a geometry update or a negative drag_ack). */
    acknowledge(ackSeq) {
      if (inFlight && ackSeq >= inFlight.seq) inFlight = null;
      if (released && ackSeq >= released.finalSeq) {
        released = null;
        onIdle();
      }
      if (drag && pendingSend) schedule();
    },
    /** Record the latency of move `ackSeq` after its curve is in the DOM (debug only). */
    drawn(ackSeq, tArrive, root) { recordLatency(moveTimes, ackSeq, tArrive, root); },
    dispose() { if (rafId) cancelAnimationFrame(rafId); },
  };
}

/**
 * Round trips of an empty message through the kernel (the widget's `debug` on): `ping(bytes)` resolves to
 * {total, up, down} in ms, the answer carrying `bytes` bytes (default none); `handle(msg)` takes the
 * kernel's custom messages (true for an answered pong).
 */
export function createPing(model) {
  const pending = new Map();
  let pingId = 0;
  return {
    ping(bytes = 0) {
      return new Promise((resolve) => {
        const id = ++pingId, t0 = performance.now(), wall0 = performance.timeOrigin + t0;
        pending.set(id, (kernelMs) => {
          const t1 = performance.now(), wall1 = performance.timeOrigin + t1;
          resolve({ total: t1 - t0, up: kernelMs - wall0, down: wall1 - kernelMs });
        });
        model.send({ type: "ping", id, bytes });
      });
    },
    handle(msg) {
      if (!msg || msg.type !== "pong" || !pending.has(msg.id)) return false;
      pending.get(msg.id)(msg.kernel_ms);
      pending.delete(msg.id);
      return true;
    },
  };
}
