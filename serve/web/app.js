// gmwm serve's page (docs/serve.md): the controls on the left send the API's requests; the
// results (the HTML report's section for the column, with its Vega plots) are shown on the
// right. Every number comes from the server, which runs the CLI's library calls; the page
// only arranges them. Strings from the server go in as text (textContent), except the
// report's section, which the server has already escaped.
(function () {
  'use strict';

  // How often a running job is polled.
  var POLL_MS = 150;
  // The studies whose plots draw an overlay (the WV and the Allan deviation's).
  var OVERLAID = ['/api/wv', '/api/fit', '/api/select'];

  var $ = function (id) { return document.getElementById(id); };
  var state = {
    dataset: null,     // /api/open's answer
    maxUpload: 0,      // the server's upload limit in bytes (/api/files)
    busy: false,       // a request or job is under way (the buttons are disabled)
    job: null,         // the running job's id (what Cancel cancels)
    document: null,    // the last fit or select document (what Export exports)
    lastRequest: null, // {endpoint, body, label, done}: run again when an overlay is set or cleared
    overlay: null,     // {format, file | text}: sent with every study while set
    overlayName: null, // the name of the file last loaded into the overlay's text box
    stability: null,   // GET /api/stability: the kinds, tau sets, quantiles and noises offered
    views: [],         // the Vega views shown, finalized when replaced
    shown: 0           // how many results were shown (a result's plots are drawn only while it is)
  };

  // Vega is the deferred script after this one: every deferred script has run when
  // DOMContentLoaded fires (this one runs before it does).
  var vegaLoaded = new Promise(function (resolve) { document.addEventListener('DOMContentLoaded', resolve); });

  // ---- numbers, messages and progress ----

  // x with `digits` significant digits as C's %g prints it (the report's tables use %.6g).
  function fmtG(x, digits) {
    if (x === null || x === undefined || !isFinite(x)) return '-';
    if (x === 0) return '0';
    var e = Math.floor(Math.log10(Math.abs(x)));
    var s;
    if (e < -4 || e >= digits) {
      var parts = x.toExponential(digits - 1).split('e');
      var n = parseInt(parts[1], 10);
      s = parts[0].replace(/(\.\d*?)0+$/, '$1').replace(/\.$/, '') + 'e' + (n < 0 ? '-' : '+') +
        (Math.abs(n) < 10 ? '0' : '') + Math.abs(n);
    } else {
      s = x.toPrecision(digits);
      if (s.indexOf('.') >= 0) s = s.replace(/0+$/, '').replace(/\.$/, '');
    }
    return s;
  }

  function status(text) { $('status').textContent = text; $('status').title = text; }

  // The error box above the results (empty text hides it).
  function showError(text) {
    var box = $('message');
    box.textContent = text;
    box.hidden = !text;
  }

  // A request to the API: JSON in and out; a refusal throws its one-line message.
  function api(method, path, body, raw) {
    var init = { method: method, headers: {} };
    if (raw !== undefined) {
      init.body = raw;
      init.headers['Content-Type'] = 'application/octet-stream';
    } else if (body !== undefined) {
      init.body = JSON.stringify(body);
      init.headers['Content-Type'] = 'application/json';
    }
    return fetch(path, init).then(function (r) {
      return r.text().then(function (text) {
        var j;
        try { j = JSON.parse(text); } catch (e) { j = { error: r.status + ' ' + r.statusText }; }
        if (!r.ok) throw new Error(j.error || (r.status + ' ' + r.statusText));
        return j;
      });
    }, function () {
      throw new Error('no answer from the server at ' + location.host + ' (has gmwm serve stopped?)');
    });
  }

  // Enables what can be done now: nothing but Cancel while busy; the studies once a recording
  // is open; Export once there is a fit or a selection; Clear while an overlay is set.
  function setBusy(busy) {
    state.busy = busy;
    var open = !!state.dataset;
    var enabled = {
      open: true, upload: true, column: open, wv: open, fit: open, select: open, overlay: open,
      stability: open && !!state.stability,
      'overlay-clear': !!state.overlay, export: !!state.document
    };
    Object.keys(enabled).forEach(function (id) { $(id).disabled = busy || !enabled[id]; });
    document.querySelector('.controls').classList.toggle('busy', busy);
    $('cancel').hidden = !busy || !state.job;
    $('progress').hidden = !busy;
  }

  // A refused request: the page says what and why, and is usable again.
  function refused(what) {
    return function (e) {
      setBusy(false);
      status(what + ': refused');
      showError(e.message);
    };
  }

  // Submits a job and polls it until it ends; `done(result, jobId)` when it ends "done".
  function runJob(endpoint, body, label, done) {
    showError('');
    state.lastRequest = { endpoint: endpoint, body: body, label: label, done: done };
    var b = Object.assign({}, body);
    if (state.overlay && OVERLAID.indexOf(endpoint) >= 0) b.overlay = state.overlay;
    var started = performance.now();
    var elapsed = function () { return ((performance.now() - started) / 1000).toFixed(1) + ' s'; };
    state.job = null;
    setBusy(true);
    status(label + ': submitting');
    $('progress').removeAttribute('value');
    return api('POST', endpoint, b).then(function (j) {
      state.job = j.job;
      setBusy(true);
      return new Promise(function (resolve) {
        (function poll() {
          api('GET', '/api/jobs/' + j.job).then(function (s) {
            if (s.state === 'queued' || s.state === 'running') {
              var p = s.progress || [0, 0];
              if (p[1] > 0) { $('progress').max = p[1]; $('progress').value = p[0]; }
              status(label + ': ' + (s.state === 'queued' ? 'waiting for a worker' :
                p[1] > 0 ? p[0] + ' of ' + p[1] : 'running') + ', ' + elapsed());
              setTimeout(poll, POLL_MS);
              return;
            }
            state.job = null;
            setBusy(false);
            // The last finished job, for a script driving the page (tests/browser).
            document.body.setAttribute('data-gmwm-job', j.job);
            document.body.setAttribute('data-gmwm-job-state', s.state);
            if (s.state === 'done') {
              status(label + ': done in ' + elapsed());
              done(s.result, j.job);
            } else if (s.state === 'cancelled') {
              status(label + ': cancelled after ' + elapsed());
            } else {
              status(label + ': failed');
              showError(s.error || 'the job failed');
            }
            resolve(s);
          }).catch(function (e) {
            state.job = null;
            refused(label)(e);
            resolve(null);
          });
        })();
      });
    }).catch(refused(label));
  }

  // ---- results ----

  // Shows a result: the report's section (already escaped by the server) and its plots, and
  // brings its top into view when the window was scrolled below it.
  function showResult(result) {
    state.views.forEach(function (v) { v.finalize(); });
    state.views = [];
    var shown = ++state.shown;
    var box = $('result');
    box.innerHTML = result.html || '';
    box.querySelectorAll('td.num').forEach(function (td) {
      if (!/\s/.test(td.textContent.trim())) td.classList.add('atom');
    });
    $('text').textContent = result.text || '';
    if (box.getBoundingClientRect().top < document.querySelector('header.app-bar').getBoundingClientRect().bottom)
      box.scrollIntoView({ block: 'start' });
    vegaLoaded.then(function () {
      if (shown === state.shown) drawPlots(result.plots || []);
    });
  }

  // Draws each plot into its container in the report's section.
  function drawPlots(plots) {
    if (typeof vega === 'undefined') {
      var missing = document.querySelector('meta[name="gmwm-vega-missing"]');
      showError('Plots unavailable: ' + (missing ? missing.content : 'Vega did not load'));
      return;
    }
    plots.forEach(function (p) {
      var el = document.getElementById(p.id);
      if (!el) return;
      try {
        var view = new vega.View(vega.parse(p.spec), { renderer: 'svg', container: el.querySelector('.view'), hover: true });
        state.views.push(view);
        view.runAsync().then(function () { el.setAttribute('data-rendered', 'svg'); })
          .catch(function (e) { showError(p.id + ': ' + e); });
      } catch (e) {
        showError(p.id + ': ' + e);
      }
    });
  }

  function column() { return $('column').value; }

  // The document Export exports (null: none), said under its button; an export shown for the
  // previous one is put away.
  function setDocument(doc, note) {
    state.document = doc;
    $('export-note').textContent = note;
    $('export-box').hidden = true;
  }

  // The settings every study takes: the dataset, the column, the units and the WV estimator.
  function baseBody() {
    var b = { dataset: state.dataset.dataset, column: column(), units: $('units').value.trim() };
    var estimator = document.querySelector('input[name=estimator]:checked').value;
    if (estimator !== 'classical') {
      b.robust = true;
      b.estimator = estimator;
      b.eff = parseFloat($('eff').value);
    }
    return b;
  }

  // ---- the model: components <-> text ----

  // The order the boxes write a model in (the CLI's own order of the processes).
  var ORDER = ['AR1', 'WN', 'QN', 'RW', 'DR', 'SIN', 'FLICKER'];

  function modelFromComponents() {
    var parts = [];
    var k = parseInt($('ar1').value, 10);
    if (k === 1) parts.push('AR1'); else if (k > 1) parts.push(k + '*AR1');
    document.querySelectorAll('#components input[type=checkbox]').forEach(function (c) {
      if (c.checked) parts.push(c.value);
    });
    var rank = function (t) { return ORDER.indexOf(t.replace(/^\d+\*/, '')); };
    parts.sort(function (a, b) { return rank(a) - rank(b); });
    $('model').value = parts.join('+');
  }

  // Ticks the boxes a typed model names (a model the boxes cannot show, e.g. with values or
  // MA1, is left as typed: the server reads the text).
  function componentsFromModel() {
    var counts = {};
    $('model').value.split('+').forEach(function (t) {
      var m = /^\s*(?:(\d+)\s*\*\s*)?([A-Za-z0-9]+)\s*$/.exec(t);
      if (m) counts[m[2].toUpperCase()] = (counts[m[2].toUpperCase()] || 0) + (m[1] ? parseInt(m[1], 10) : 1);
    });
    $('ar1').value = String(Math.min(counts.AR1 || counts.GM || 0, 5));
    document.querySelectorAll('#components input[type=checkbox]').forEach(function (c) {
      c.checked = !!counts[c.value];
    });
  }

  // ---- the recording ----

  function option(value, text) {
    var o = document.createElement('option');
    o.value = value;
    o.textContent = text;
    return o;
  }

  function megabytes(bytes) { return (bytes / 1e6).toFixed(bytes < 1e7 ? 1 : 0) + ' MB'; }

  function loadFiles() {
    return api('GET', '/api/files').then(function (f) {
      $('folder-name').textContent = f.folder;
      state.maxUpload = f.max_upload || 0;
      if (state.maxUpload) $('upload-limit').textContent = '(up to ' + megabytes(state.maxUpload) + ')';
      var sel = $('file');
      sel.textContent = '';
      f.files.forEach(function (e) { sel.appendChild(option(e.path, e.path + ' (' + megabytes(e.size) + ')')); });
      if (!f.files.length) sel.appendChild(option('', '(no recording in this folder: upload one)'));
      if (f.truncated) sel.appendChild(option('', '(the listing stops at its limit: the folder holds more)'));
      f.configs.forEach(function (e) { $('overlay-file').appendChild(option(e.path, e.path)); });
      status('ready');
      performance.mark('gmwm-ready');  // the page is usable (timed by tests/browser)
    }).catch(function (e) { status('the server did not answer'); showError(e.message); });
  }

  function opened(d) {
    state.dataset = d;
    setDocument(null, 'Exports the last fit, or the selection\u2019s chosen model.');
    $('ranking').hidden = true;
    $('ranking-note').textContent = '';
    var sel = $('column');
    sel.textContent = '';
    d.columns.forEach(function (c) {
      var facts = [c.kind, c.unit].filter(function (x) { return x; }).join(', ');
      sel.appendChild(option(c.name, c.name + (facts ? ' (' + facts + ')' : '')));
    });
    hatColumns(d.columns);
    var hours = d.n / d.freq / 3600;
    $('dataset-facts').textContent = d.name + ': ' + d.n.toLocaleString('en') + ' samples at ' + fmtG(d.freq, 6) +
      ' Hz' + (d.freq_known ? '' : ' (as given)') + ', ' +
      (hours >= 1 ? hours.toFixed(2) + ' h' : (hours * 3600).toFixed(1) + ' s') + ', ' + d.columns.length +
      ' column' + (d.columns.length === 1 ? '' : 's') + (d.timing ? '. ' + d.timing : '') +
      (d.notes || []).map(function (n) { return '. ' + n; }).join('');
    setBusy(false);
    runWv();
  }

  // /api/open's body: the recording (`which`) and the sampling rate when one is typed.
  function openBody(which) {
    var f = parseFloat($('freq').value);
    if (f > 0) which.freq = f;
    return which;
  }

  function openFile() {
    var file = $('file').value;
    if (!file) { showError('Choose a recording, or upload one.'); return; }
    showError('');
    status('reading ' + file + '\u2026');
    setBusy(true);
    api('POST', '/api/open', openBody({ file: file })).then(opened).catch(refused('opening ' + file));
  }

  function uploadFile() {
    var f = $('upload').files[0];
    if (!f) return;
    if (state.maxUpload && f.size > state.maxUpload) {
      showError(f.name + ' is ' + megabytes(f.size) + ': more than the server takes (' + megabytes(state.maxUpload) +
        ', gmwm serve --max-upload); put it in the served folder instead.');
      $('upload').value = '';
      return;
    }
    showError('');
    status('uploading ' + f.name + ' (' + megabytes(f.size) + ')\u2026');
    setBusy(true);
    api('POST', '/api/upload?name=' + encodeURIComponent(f.name), undefined, f).then(function (u) {
      status('reading ' + u.name + '\u2026');
      return api('POST', '/api/open', openBody({ upload: u.upload }));
    }).then(opened).catch(refused('uploading ' + f.name));
    // Cleared, so that choosing the same file again (say with a sampling rate typed since)
    // uploads it again.
    $('upload').value = '';
  }

  // ---- the studies ----

  function runWv() {
    runJob('/api/wv', baseBody(), 'WV of ' + column(), showResult);
  }

  function runFit() {
    var body = baseBody();
    body.model = $('model').value.trim();
    body.omega = $('omega').value;
    body.first_level = $('first-level').value;
    runJob('/api/fit', body, 'fit of ' + body.model, function (r) {
      setDocument(r.document, 'Exports the fit of ' + body.model + ' on ' + body.column + '.');
      document.querySelectorAll('#ranking tr.active').forEach(function (x) { x.classList.remove('active'); });
      showResult(r);
      setBusy(false);
    });
  }

  function runSelect() {
    var body = baseBody();
    body.model = $('maximal').value.trim();
    body.first_level = $('first-level').value;
    runJob('/api/select', body, 'selection over ' + body.model, function (r, job) {
      var best = r.document.columns[0].best;
      setDocument(r.document, 'Exports the selection\u2019s chosen model' + (best ? ' ' + best : '') + ' on ' +
        body.column + '.');
      showResult(r);
      showRanking(r.document.columns[0], job);
      setBusy(false);
    });
  }

  // The ranking as a table: each row shows its model's fit when clicked (or Enter).
  function showRanking(col, job) {
    var tbody = $('ranking').querySelector('tbody');
    tbody.textContent = '';
    col.ranking.forEach(function (r, i) {
      var tr = document.createElement('tr');
      tr.tabIndex = 0;
      tr.setAttribute('data-row', String(i + 1));
      [String(r.rank), r.model, fmtG(r.criterion, 6), fmtG(r.gof_p_value, 2)].forEach(function (text, k) {
        var td = document.createElement('td');
        td.textContent = text;
        if (k === 1) td.className = 'model';
        tr.appendChild(td);
      });
      tr.title = r.effective_parameters + ' parameters, objective ' + fmtG(r.objective, 6) + ', optimism ' +
        fmtG(r.optimism, 4) + (r.members && r.members.length > 1 ? '; ' + (r.members.length - 1) +
        ' other candidate(s) fell onto it' : '');
      if (i === 0) tr.classList.add('active');
      var show = function () { showRow(job, i + 1, col.ranking.length, tr); };
      tr.addEventListener('click', show);
      tr.addEventListener('keydown', function (e) { if (e.key === 'Enter') show(); });
      tbody.appendChild(tr);
    });
    $('ranking').hidden = false;
    $('ranking-note').textContent = col.ranking.length + ' distinct models of ' + col.models +
      ' candidates; click a row to see its fit (the first refitted with intervals, the others as the ' +
      'selection fitted them, under its shared Omega).';
  }

  function showRow(job, row, rows, tr) {
    if (state.busy) return;
    showError('');
    status('ranking row ' + row + ' of ' + rows + '\u2026');
    api('GET', '/api/jobs/' + job + '/ranking/' + row).then(function (r) {
      document.querySelectorAll('#ranking tr.active').forEach(function (x) { x.classList.remove('active'); });
      tr.classList.add('active');
      showResult(r);
      status('ranking row ' + row + ' of ' + rows + ': ' + r.model +
        (row > 1 ? ' (as the selection fitted it; Fit it for its intervals)' : ''));
      $('model').value = r.model;
      componentsFromModel();
    }).catch(function (e) { status('ranking row ' + row + ': refused'); showError(e.message); });
  }

  // ---- the frequency-stability deviations ----

  // The choices the library offers (GET /api/stability): a box per kind, its defaults ticked.
  function loadStability() {
    return api('GET', '/api/stability').then(function (c) {
      state.stability = c;
      var box = $('stability-kinds');
      box.textContent = '';
      c.kinds.forEach(function (k) {
        var label = document.createElement('label');
        label.title = k.title + (k.time_units ? ' (in the phase\u2019s unit)' : '');
        var input = document.createElement('input');
        input.type = 'checkbox';
        input.value = k.name;
        input.checked = k.default;
        label.appendChild(input);
        label.appendChild(document.createTextNode(' ' + k.name));
        box.appendChild(label);
      });
      var taus = $('stability-taus');
      taus.textContent = '';
      c.taus.forEach(function (t) { taus.appendChild(option(t, t)); });
      taus.appendChild(option('list', 'times listed'));
      taus.value = c.default_taus;
      var quantiles = $('stability-intervals');
      quantiles.textContent = '';
      c.intervals.forEach(function (m) { quantiles.appendChild(option(m, m)); });
      quantiles.value = c.default_intervals;
      c.noises.forEach(function (n) {
        $('stability-noise').appendChild(option(String(n.alpha), 'alpha ' + n.alpha + ': ' + n.name));
      });
      $('stability-confidence').placeholder = fmtG(c.confidence, 4) + ' (one sigma)';
      setBusy(state.busy);
    }).catch(function (e) { showError('Frequency stability: ' + e.message); });
  }

  // The hat's columns A, B, C: the recording's first three by default; "(none)" where it has
  // fewer (the server then says what the hat needs).
  var HAT_SELECTS = ['stability-hat-a', 'stability-hat-b', 'stability-hat-c'];
  function hatColumns(columns) {
    HAT_SELECTS.forEach(function (id, i) {
      var sel = $(id);
      sel.textContent = '';
      sel.appendChild(option('', '(none)'));
      columns.forEach(function (c) { sel.appendChild(option(c.name, c.name)); });
      sel.value = i < columns.length ? columns[i].name : '';
    });
  }

  // POST /api/stability's body: the column (with the hat, "hat" and its three "columns"), the
  // ticked kinds, the averaging times, the interval's settings (a blank confidence is the
  // server's default, Stable32's one sigma, to its last digit).
  function stabilityBody() {
    var b = { dataset: state.dataset.dataset, units: $('units').value.trim(),
      data: $('stability-data').value, intervals: $('stability-intervals').value, kind: [] };
    if ($('stability-hat').checked) {
      b.hat = true;
      b.columns = HAT_SELECTS.map(function (id) { return $(id).value; }).filter(function (c) { return c; });
    } else {
      b.column = column();
    }
    document.querySelectorAll('#stability-kinds input:checked').forEach(function (c) { b.kind.push(c.value); });
    var taus = $('stability-taus').value;
    b.taus = taus === 'list' ? $('stability-list').value.trim() : taus;
    var confidence = $('stability-confidence').value.trim();
    if (confidence) b.confidence = parseFloat(confidence);
    var noise = $('stability-noise').value;
    if (noise) b.noise_alpha = parseInt(noise, 10);
    return b;
  }

  function runStability() {
    var body = stabilityBody();
    runJob('/api/stability', body, body.hat ? 'three-cornered hat of ' + body.columns.join(', ') :
      'stability of ' + body.column, showResult);
  }

  // ---- the overlay ----

  // The overlay's source: a file in the folder, else the text box (named after the file it was
  // loaded from, if any).
  function overlayBody() {
    var o = { format: $('overlay-format').value };
    if ($('overlay-file').value) {
      o.file = $('overlay-file').value;
    } else {
      o.text = $('overlay-text').value;
      if (state.overlayName) o.name = state.overlayName;
    }
    return o;
  }

  // The baseline as the server read it: its name, its model and how each figure was converted.
  function showOverlay(r) {
    var box = $('overlay-model');
    box.textContent = '';
    var head = document.createElement('div');
    var name = document.createElement('strong');
    name.textContent = r.name.split(':')[0] + (r.source ? ' (' + r.source + ')' : '');
    var model = document.createElement('code');
    model.textContent = r.model;
    head.appendChild(name);
    head.appendChild(document.createTextNode(' = '));
    head.appendChild(model);
    box.appendChild(head);
    var list = document.createElement('ul');
    list.className = 'facts';
    (r.conversions || []).forEach(function (c) {
      var li = document.createElement('li');
      li.textContent = c;
      list.appendChild(li);
    });
    box.appendChild(list);
  }

  function applyOverlay() {
    var o = overlayBody();
    if (o.text !== undefined && !o.text.trim()) {
      showError('Overlay: choose a file in the folder, or paste or load its text.');
      return;
    }
    var b = Object.assign({ dataset: state.dataset.dataset, column: column(), units: $('units').value.trim() }, o);
    showError('');
    api('POST', '/api/overlay', b).then(function (r) {
      state.overlay = o;
      showOverlay(r);
      setBusy(false);
      rerun();
    }).catch(function (e) { status('overlay: refused'); showError(e.message); });
  }

  function clearOverlay() {
    state.overlay = null;
    $('overlay-model').textContent = '';
    setBusy(false);
    rerun();
  }

  // Runs the last study again when it draws the overlay (an overlay changes its plots).
  function rerun() {
    var r = state.lastRequest;
    if (r && OVERLAID.indexOf(r.endpoint) >= 0) runJob(r.endpoint, r.body, r.label, r.done);
  }

  // A file's text read into the overlay's text box (the folder's file choice then cleared).
  function loadOverlayFile() {
    var f = $('overlay-load').files[0];
    if (!f) return;
    f.text().then(function (text) {
      $('overlay-text').value = text;
      $('overlay-file').value = '';
      state.overlayName = f.name;
    }, function (e) { showError(f.name + ': ' + e.message); });
  }

  // ---- the export ----

  // Offers `content` as a download named `filename`.
  function download(filename, content) {
    var a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([content], { type: 'text/plain' }));
    a.download = filename;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(function () { URL.revokeObjectURL(a.href); }, 1000);
  }

  function exportModel() {
    if (!state.document) return;
    var format = $('export-format');
    var body = { result: state.document, format: format.value, units: $('units').value.trim() };
    var rate = parseFloat($('export-rate').value);
    if (rate > 0) body.rate = rate;
    var inflate = parseFloat($('export-inflate').value);
    if (inflate > 0) body.inflate = inflate;
    if ($('export-partial').checked) body.partial = true;
    showError('');
    api('POST', '/api/export', body).then(function (e) {
      download(e.filename, e.content);
      var warnings = e.warnings || [];
      // The format's name without the file name its option adds in brackets.
      $('export-summary').textContent = e.filename + ', for ' + format.selectedOptions[0].textContent.replace(/ \(.*\)$/, '');
      var list = $('export-warnings');
      list.textContent = '';
      warnings.forEach(function (w) {
        var li = document.createElement('li');
        li.textContent = w;
        list.appendChild(li);
      });
      list.hidden = !warnings.length;
      $('export-text').textContent = e.text || '';
      $('export-preview').textContent = e.content;
      var side = $('export-sidecar');
      side.textContent = '';
      side.hidden = !e.sidecar;
      if (e.sidecar) {
        var a = document.createElement('a');
        a.href = '#';
        a.textContent = e.sidecar.filename;
        a.addEventListener('click', function (ev) { ev.preventDefault(); download(e.sidecar.filename, e.sidecar.content); });
        side.appendChild(document.createTextNode('Its header, as a separate file (the format has no comments): '));
        side.appendChild(a);
      }
      $('export-box').hidden = false;
      $('export-box').scrollIntoView({ block: 'nearest' });
      status('exported ' + e.filename + (warnings.length ? ' (' + warnings.length + ' warning' +
        (warnings.length === 1 ? '' : 's') + ', shown with it)' : ''));
    }).catch(function (e) { status('export: refused'); showError(e.message); });
  }

  function cancelJob() {
    if (!state.job) return;
    api('DELETE', '/api/jobs/' + state.job).catch(function (e) { showError(e.message); });
    status('cancelling\u2026');
  }

  // ---- wiring ----

  $('open').addEventListener('click', openFile);
  $('upload').addEventListener('change', uploadFile);
  $('column').addEventListener('change', runWv);
  $('wv').addEventListener('click', runWv);
  $('fit').addEventListener('click', runFit);
  $('select').addEventListener('click', runSelect);
  $('stability').addEventListener('click', runStability);
  $('stability-hat').addEventListener('change', function () {
    $('stability-hat-columns').hidden = !$('stability-hat').checked;
  });
  $('stability-taus').addEventListener('change', function () {
    $('stability-list-label').hidden = $('stability-taus').value !== 'list';
  });
  $('overlay').addEventListener('click', applyOverlay);
  $('overlay-clear').addEventListener('click', clearOverlay);
  $('overlay-load').addEventListener('change', loadOverlayFile);
  $('overlay-text').addEventListener('input', function () { state.overlayName = null; });
  $('export').addEventListener('click', exportModel);
  $('cancel').addEventListener('click', cancelJob);
  document.querySelectorAll('input[name=estimator]').forEach(function (r) {
    r.addEventListener('change', function () { $('eff').disabled = r.value === 'classical'; });
  });
  document.querySelectorAll('#components input, #ar1').forEach(function (c) {
    c.addEventListener('change', modelFromComponents);
  });
  $('model').addEventListener('input', componentsFromModel);
  // Enter in a model field (or the stability's times or confidence) runs it, as its button would.
  var enterRuns = [['model', 'fit'], ['maximal', 'select'], ['stability-list', 'stability'],
    ['stability-confidence', 'stability']];
  enterRuns.forEach(function (p) {
    $(p[0]).addEventListener('keydown', function (e) { if (e.key === 'Enter' && !$(p[1]).disabled) $(p[1]).click(); });
  });
  setBusy(false);
  loadFiles();
  loadStability();
})();
