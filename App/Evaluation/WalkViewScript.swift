/// The trainer's page script: one constant, identical for every walk (no text of it is generated from data).
/// It reads the walk from `<script type="application/json" id="walk-data">` with `JSON.parse`, and moves the
/// playhead: the scrubber (`#scrubber`), Play/Pause, the speed menu, a click or drag on the timeline, and the
/// URL fragment `#t=SECONDS` (`#t=SECONDS&play` also starts playing; the hooks the headless-browser tests use). At each moment it draws on the
/// floor plan the true and estimated positions, the particle cloud and hypotheses of the latest kept moment,
/// the sightings of the last second with the sign each matched, and the route in force; and it writes the
/// state panel (confidence, tracking, what was said and felt, sightings, wrong turns and re-routes). Data only
/// reaches the page through `setAttribute` with numbers and `textContent`; nothing becomes markup or code.
enum WalkViewScript {
    static let source = """
        <script>
        (function () {
          'use strict';
          var NS = 'http://www.w3.org/2000/svg';
          var floorButtons = document.querySelectorAll('nav button[data-floor]');
          var sections = document.querySelectorAll('section.floor');
          var follow = true;
          function revealFloor(k) {
            sections.forEach(function (s) {
              s.style.display = s.getAttribute('data-floor') === String(k) ? 'block' : 'none';
            });
            floorButtons.forEach(function (b) {
              b.setAttribute('aria-pressed', b.getAttribute('data-floor') === String(k) ? 'true' : 'false');
            });
          }
          floorButtons.forEach(function (b) {
            b.addEventListener('click', function () { follow = false; revealFloor(b.getAttribute('data-floor')); });
          });
          var snapshots = document.getElementById('show-snapshots');
          if (snapshots) {
            snapshots.addEventListener('change', function () {
              document.querySelectorAll('g.snapshot').forEach(function (g) {
                g.style.display = snapshots.checked ? 'inline' : 'none';
              });
            });
          }
          var dataNode = document.getElementById('walk-data');
          if (!dataNode) { return; }
          var D = JSON.parse(dataNode.textContent);
          var F = D.frames, hasTruth = F.tx.length > 0;
          var cloudT = D.clouds.map(function (c) { return c.t; });
          var routeT = D.routes.map(function (r) { return r.t; });
          var sightT = D.sightings.map(function (s) { return s.t; });
          var scrub = document.getElementById('scrubber');
          var playButton = document.getElementById('play');
          var speed = document.getElementById('speed');
          var playhead = document.getElementById('playhead');
          var timeline = document.getElementById('timeline');
          var current = D.initial, shownCloud = -2, shownRoute = -2;

          function atOrBefore(arr, v) {
            var lo = 0, hi = arr.length - 1, best = -1;
            while (lo <= hi) {
              var mid = (lo + hi) >> 1;
              if (arr[mid] <= v) { best = mid; lo = mid + 1; } else { hi = mid - 1; }
            }
            return best;
          }
          function px(f, xcm) { var g = D.floors[f]; return ((xcm / 100 + g.ox) * g.s).toFixed(1); }
          function py(f, ycm) { var g = D.floors[f]; return ((g.oy - ycm / 100) * g.s).toFixed(1); }
          function el(name, attrs) {
            var e = document.createElementNS(NS, name);
            Object.keys(attrs).forEach(function (k) { e.setAttribute(k, String(attrs[k])); });
            return e;
          }
          function clear(g) { while (g.firstChild) { g.removeChild(g.firstChild); } }
          function live(f, name) { return document.getElementById('live-' + name + '-' + f); }
          function setText(id, text) { var e = document.getElementById(id); if (e) { e.textContent = text; } }
          function secs(ms) { return (ms / 1000).toFixed(1) + ' s'; }
          function place(marker, f, show, xcm, ycm, hmrad) {
            if (!marker) { return; }
            marker.style.display = show ? 'inline' : 'none';
            if (!show) { return; }
            var x = px(f, xcm), y = py(f, ycm);
            marker.setAttribute('transform', 'translate(' + x + ',' + y + ') rotate(' + (-hmrad * 0.18 / Math.PI).toFixed(1) + ')');
          }

          function drawCloud(k) {
            if (k === shownCloud) { return; }
            shownCloud = k;
            for (var f = 0; f < D.floors.length; f++) {
              var g = live(f, 'cloud'), h = live(f, 'hyp');
              if (g) { clear(g); }
              if (h) { clear(h); }
            }
            if (k < 0) { return; }
            var c = D.clouds[k], i, fl;
            for (i = 0; i + 2 < c.p.length; i += 3) {
              fl = live(c.p[i], 'cloud');
              if (fl) { fl.appendChild(el('circle', { cx: px(c.p[i], c.p[i + 1]), cy: py(c.p[i], c.p[i + 2]), r: 1.6 })); }
            }
            for (i = 0; i + 5 < c.hyp.length; i += 6) {
              fl = live(c.hyp[i], 'hyp');
              if (!fl) { continue; }
              var r = Math.max(4, c.hyp[i + 5] / 100 * D.floors[c.hyp[i]].s);
              var ring = el('circle', { cx: px(c.hyp[i], c.hyp[i + 1]), cy: py(c.hyp[i], c.hyp[i + 2]), r: r.toFixed(1),
                'stroke-width': (1 + 3 * c.hyp[i + 4] / 1000).toFixed(1) });
              var title = el('title', {});
              title.textContent = 'hypothesis: weight ' + (c.hyp[i + 4] / 10).toFixed(0) + ' %, spread ' + (c.hyp[i + 5] / 100).toFixed(1) + ' m';
              ring.appendChild(title);
              fl.appendChild(ring);
            }
          }
          function drawRoute(k) {
            if (k === shownRoute) { return; }
            shownRoute = k;
            for (var f = 0; f < D.floors.length; f++) {
              var line = live(f, 'route');
              if (!line) { continue; }
              var pts = [];
              if (k >= 0) {
                var p = D.routes[k].p;
                for (var i = 0; i + 2 < p.length; i += 3) { if (p[i] === f) { pts.push(px(f, p[i + 1]) + ',' + py(f, p[i + 2])); } }
              }
              line.setAttribute('points', pts.join(' '));
            }
          }
          function recent(kinds, tMs, windowMs, count) {
            var out = [];
            for (var i = D.events.length - 1; i >= 0 && out.length < count; i--) {
              var e = D.events[i];
              if (e.t > tMs) { continue; }
              if (e.t < tMs - windowMs) { break; }
              if (kinds.indexOf(e.k) >= 0) { out.push(e); }
            }
            return out;
          }
          function describe(list, tMs) {
            return list.length === 0 ? '-' : list.map(function (e) {
              return e.text + ' (' + secs(tMs - e.t) + ' ago)';
            }).join(' | ');
          }

          function setTime(tMs) {
            if (!isFinite(tMs)) { return; }
            tMs = Math.max(D.t0, Math.min(D.t1, Math.round(tMs)));
            current = tMs;
            var i = Math.max(0, atOrBefore(F.t, tMs));
            var estFloor = F.f[i], trueFloor = hasTruth ? F.tf[i] : -1;
            var shown = trueFloor >= 0 ? trueFloor : estFloor;
            if (follow && shown >= 0) { revealFloor(shown); }
            for (var f = 0; f < D.floors.length; f++) {
              place(live(f, 'est'), f, estFloor === f, F.x[i], F.y[i], F.h[i]);
              place(live(f, 'truth'), f, hasTruth && trueFloor === f, hasTruth ? F.tx[i] : 0, hasTruth ? F.ty[i] : 0,
                    hasTruth ? F.th[i] : 0);
              var est = live(f, 'est');
              if (est) { est.setAttribute('class', F.loc[i] ? 'est localized' : 'est searching'); }
              var rays = live(f, 'rays');
              if (rays) { clear(rays); }
            }
            drawCloud(atOrBefore(cloudT, tMs));
            drawRoute(atOrBefore(routeT, tMs));

            var lastSight = atOrBefore(sightT, tMs), sightTexts = [], sightSeen = {};
            for (var k = lastSight; k >= 0 && D.sightings[k].t > tMs - 1000; k--) {
              var s = D.sightings[k], g = live(s.f, 'rays');
              if (!g) { continue; }
              g.appendChild(el('line', { x1: px(s.f, s.x0), y1: py(s.f, s.y0), x2: px(s.f, s.x1), y2: py(s.f, s.y1), 'class': 'ray' }));
              if (s.match !== '') {
                g.appendChild(el('circle', { cx: px(s.f, s.sx), cy: py(s.f, s.sy), r: 9, 'class': 'matched' }));
              }
              var words = s.kind + ' sign ' + (s.match !== '' ? 'matched ' + s.match : 'matched no sign');
              if (hasTruth && s.truth !== s.match) { words += ', truly ' + (s.truth !== '' ? s.truth : 'no sign'); }
              if (!sightSeen.hasOwnProperty(words)) {
                sightSeen[words] = sightTexts.length;
                sightTexts.push({ words: words, count: 0, md: s.md });
              }
              sightTexts[sightSeen[words]].count += 1;
            }

            setText('st-time', secs(tMs) + ' of ' + secs(D.t1));
            setText('st-conf', (F.c[i] / 10).toFixed(0) + ' %');
            var bar = document.getElementById('st-conf-bar');
            if (bar) { bar.setAttribute('value', (F.c[i] / 1000).toFixed(3)); }
            setText('st-loc', F.loc[i] ? 'localized' : 'searching (not localized)');
            setText('st-hyp', String(F.nh[i]));
            setText('st-track', ['normal', 'limited', 'lost'][F.trk[i]]);
            setText('st-err', !hasTruth ? 'no truth' : (F.err[i] < 0 ? 'on another floor' : (F.err[i] / 100).toFixed(2) + ' m'));
            setText('st-said', describe(recent(['said', 'prompt'], tMs, 15000, 3), tMs));
            setText('st-felt', describe(recent(['haptic', 'wrong'], tMs, 3000, 3), tMs));
            setText('st-sight', sightTexts.length === 0 ? '-' : sightTexts.slice(0, 3).map(function (x) {
              return x.words + (x.md > 0 ? ' (' + (x.md / 100).toFixed(1) + ' m off)' : '') + (x.count > 1 ? ', ' + x.count + ' times' : '');
            }).join(' | '));
            setText('st-nav', describe(recent(['wrong', 'reroute'], tMs, 10000, 2), tMs));

            if (scrub) {
              scrub.value = (tMs / 1000).toFixed(1);
              scrub.setAttribute('value', scrub.value);
              scrub.setAttribute('aria-valuetext', secs(tMs));
            }
            if (playhead) {
              var x = D.timelineLeft + (D.t1 > D.t0 ? (tMs - D.t0) / (D.t1 - D.t0) : 0) * (D.timelineWidth - D.timelineLeft - 10);
              playhead.setAttribute('x1', x.toFixed(1));
              playhead.setAttribute('x2', x.toFixed(1));
            }
            document.body.setAttribute('data-t', (tMs / 1000).toFixed(1));
          }

          var playing = false, lastFrame = null;
          // A 40 ms timer rather than animation frames: timers also run in a headless browser's virtual time.
          function step() {
            if (!playing) { return; }
            var now = window.performance.now();
            setTime(current + Math.max(0, now - lastFrame) * Number(speed ? speed.value : 1));
            lastFrame = now;
            if (current >= D.t1) { toggle(); }
            if (playing) { window.setTimeout(step, 40); }
          }
          function toggle() {
            playing = !playing;
            lastFrame = window.performance.now();
            if (playButton) {
              playButton.textContent = playing ? 'Pause' : 'Play';
              playButton.setAttribute('aria-pressed', playing ? 'true' : 'false');
            }
            if (playing) {
              if (current >= D.t1) { setTime(D.t0); }
              window.setTimeout(step, 40);
            }
          }
          if (playButton) { playButton.addEventListener('click', toggle); }
          if (scrub) { scrub.addEventListener('input', function () { setTime(Number(scrub.value) * 1000); }); }
          if (timeline) {
            var dragging = false;
            var seek = function (ev) {
              var box = timeline.getBoundingClientRect();
              var x = (ev.clientX - box.left) * (D.timelineWidth / box.width);
              var frac = (x - D.timelineLeft) / (D.timelineWidth - D.timelineLeft - 10);
              setTime(D.t0 + Math.max(0, Math.min(1, frac)) * (D.t1 - D.t0));
            };
            timeline.addEventListener('pointerdown', function (ev) { dragging = true; seek(ev); });
            window.addEventListener('pointermove', function (ev) { if (dragging) { seek(ev); } });
            window.addEventListener('pointerup', function () { dragging = false; });
          }
          function fromFragment() {
            var m = /^#t=([0-9]+(?:[.][0-9]+)?)(&play)?$/.exec(window.location.hash);
            if (!m) { return false; }
            setTime(Number(m[1]) * 1000);
            if (m[2] && !playing) { toggle(); }
            return true;
          }
          window.addEventListener('hashchange', fromFragment);
          if (!fromFragment()) { setTime(D.initial); }
        })();
        </script>
        """
}
