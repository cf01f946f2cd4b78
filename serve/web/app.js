// gmwm serve's page (docs/serve.md): the controls on the left send the API's requests; the
// results (the HTML report's section for the column, with its Vega plots) are shown on the
// right. Every number comes from the server, which runs the CLI's library calls; the page
// only arranges them. Strings from the server go in as text (textContent), except the
// report's section, which the server has already escaped.
(function () {
  'use strict';

  // How often a running job is polled, and how long a request may take before the page
  // says so (the server answers every request at once; jobs report their progress).
  var POLL_MS = 150;

  var $ = function (id) { return document.getElementById(id); };
  var state = {
    dataset: null,     // /api/open's answer
    job: null,         // the running job's id
    document: null,    // the last fit or select document (what Export exports)
    selectJob: null,   // the last finished selection's job id (its ranking rows)
    lastRequest: null, // {endpoint, body}: re-run when an overlay is set or cleared
    overlay: null,     // {format, file | text}
    views: []          // the Vega views shown, finalized when replaced
  };

  // ---- messages and progress ----

  function status(text) { $('status').textContent = text; }

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
    });
  }

  function setBusy(busy) {
    ['open', 'wv', 'fit', 'select', 'overlay', 'overlay-clear', 'export'].forEach(function (id) {
      $(id).disabled = busy || (id !== 'open' && !state.dataset) || (id === 'export' && !state.document) ||
        (id === 'overlay-clear' && !state.overlay);
    });
    $('cancel').hidden = !busy || !state.job;
    $('progress').hidden = !busy;
  }

  // Submits a job and polls it; `done(result)` when it ends "done".
  function runJob(endpoint, body, label, done) {
    showError('');
    state.lastRequest = { endpoint: endpoint, body: body, label: label, done: done };
    var b = Object.assign({}, body);
    if (state.overlay) b.overlay = state.overlay;
    var started = performance.now();
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
                p[1] > 0 ? p[0] + ' of ' + p[1] : 'running') + ', ' +
                ((performance.now() - started) / 1000).toFixed(1) + ' s');
              setTimeout(poll, POLL_MS);
              return;
            }
            state.job = null;
            setBusy(false);
            var seconds = ((performance.now() - started) / 1000).toFixed(2);
            // The last finished job, for a script driving the page (tests/browser).
            document.body.setAttribute('data-gmwm-job', j.job);
            document.body.setAttribute('data-gmwm-job-state', s.state);
            if (s.state === 'done') {
              status(label + ': done in ' + seconds + ' s');
              done(s.result, j.job);
            } else if (s.state === 'cancelled') {
              status(label + ': cancelled after ' + seconds + ' s');
            } else {
              status(label + ': failed');
              showError(s.error || 'the job failed');
            }
            resolve(s);
          }).catch(function (e) {
            state.job = null;
            setBusy(false);
            status(label + ': lost contact with the server');
            showError(e.message);
            resolve(null);
          });
        })();
      });
    }).catch(function (e) {
      setBusy(false);
      status(label + ': refused');
      showError(e.message);
    });
  }

  // ---- results ----

  // Shows a result: the report's section (already escaped by the server) and its plots.
  function showResult(result) {
    state.views.forEach(function (v) { v.finalize(); });
    state.views = [];
    var box = $('result');
    box.innerHTML = result.html || '';
    $('text').textContent = result.text || '';
    if (typeof vega === 'undefined') {
      showError('Plots unavailable: ' + (window.gmwmVegaMissing || 'Vega did not load'));
      return;
    }
    (result.plots || []).forEach(function (p) {
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

  // The settings every study takes: the dataset, the column, the units and the WV estimator.
  function baseBody() {
    var b = { dataset: state.dataset.dataset, column: column(), units: $('units').value.trim() };
    if (document.querySelector('input[name=estimator]:checked').value === 'robust') {
      b.robust = true;
      b.eff = parseFloat($('eff').value);
    }
    return b;
  }

  // ---- the model: components <-> text ----

  var ORDER = ['WN', 'QN', 'RW', 'DR', 'SIN', 'FLICKER'];

  function modelFromComponents() {
    var parts = [];
    var k = parseInt($('ar1').value, 10);
    if (k === 1) parts.push('AR1'); else if (k > 1) parts.push(k + '*AR1');
    document.querySelectorAll('#components input[type=checkbox]').forEach(function (c) {
      if (c.checked) parts.push(c.value);
    });
    parts.sort(function (a, b) {
      return (a.indexOf('AR1') >= 0 ? -1 : ORDER.indexOf(a)) - (b.indexOf('AR1') >= 0 ? -1 : ORDER.indexOf(b));
    });
    $('model').value = parts.join('+');
  }

  // Ticks the boxes a typed model names (a model the boxes cannot show, e.g. with values or
  // MA1, is left as typed: the server reads the text).
  function componentsFromModel() {
    var counts = {};
    $('model').value.split('+').forEach(function (t) {
      var m = /^\s*(?:(\d+)\s*\*\s*)?([A-Z0-9]+)\s*$/.exec(t);
      if (m) counts[m[2]] = (counts[m[2]] || 0) + (m[1] ? parseInt(m[1], 10) : 1);
    });
    var ar1 = Math.min(counts.AR1 || 0, 5);
    $('ar1').value = String(ar1);
    document.querySelectorAll('#components input[type=checkbox]').forEach(function (c) {
      c.checked = !!counts[c.value];
    });
  }

  // ---- actions ----

  function loadFiles() {
    return api('GET', '/api/files').then(function (f) {
      $('folder-name').textContent = f.folder;
      var sel = $('file');
      sel.textContent = '';
      f.files.forEach(function (e) {
        var o = document.createElement('option');
        o.value = e.path;
        o.textContent = e.path + ' (' + (e.size / 1e6).toFixed(1) + ' MB)';
        sel.appendChild(o);
      });
      if (!f.files.length) {
        var none = document.createElement('option');
        none.value = '';
        none.textContent = '(no recording in this folder: upload one)';
        sel.appendChild(none);
      }
      var cfg = $('overlay-file');
      f.configs.forEach(function (e) {
        var o = document.createElement('option');
        o.value = e.path;
        o.textContent = e.path;
        cfg.appendChild(o);
      });
      status('ready');
    }).catch(function (e) { status('the server did not answer'); showError(e.message); });
  }

  function opened(d) {
    state.dataset = d;
    state.document = null;
    var sel = $('column');
    sel.textContent = '';
    d.columns.forEach(function (c) {
      var o = document.createElement('option');
      o.value = c.name;
      o.textContent = c.name + (c.kind ? ' (' + c.kind + ')' : '');
      sel.appendChild(o);
    });
    sel.disabled = false;
    $('dataset-facts').textContent = d.name + ': ' + d.n.toLocaleString('en') + ' samples at ' +
      d.freq.toPrecision(6) + ' Hz (' + (d.n / d.freq / 3600).toFixed(2) + ' h), ' + d.columns.length + ' column(s)' +
      (d.timing ? '. ' + d.timing : '');
    setBusy(false);
    runWv();
  }

  function openBody(extra) {
    var b = extra;
    var f = parseFloat($('freq').value);
    if (f > 0) b.freq = f;
    return b;
  }

  function openFile() {
    var file = $('file').value;
    if (!file) { showError('Choose a recording, or upload one.'); return; }
    showError('');
    status('reading ' + file + '…');
    setBusy(true);
    api('POST', '/api/open', openBody({ file: file })).then(opened).catch(function (e) {
      setBusy(false);
      status('not opened');
      showError(e.message);
    });
  }

  function uploadFile() {
    var f = $('upload').files[0];
    if (!f) return;
    showError('');
    status('uploading ' + f.name + ' (' + (f.size / 1e6).toFixed(1) + ' MB)…');
    setBusy(true);
    api('POST', '/api/upload?name=' + encodeURIComponent(f.name), undefined, f).then(function (u) {
      status('reading ' + u.name + '…');
      return api('POST', '/api/open', openBody({ upload: u.upload }));
    }).then(opened).catch(function (e) {
      setBusy(false);
      status('not opened');
      showError(e.message);
    });
  }

  function runWv() {
    runJob('/api/wv', baseBody(), 'WV of ' + column(), function (r) {
      showResult(r);
    });
  }

  function runFit(model) {
    var body = baseBody();
    body.model = model || $('model').value.trim();
    body.omega = $('omega').value;
    runJob('/api/fit', body, 'fit of ' + body.model, function (r) {
      state.document = r.document;
      $('export-note').textContent = 'Exports the fit of ' + body.model + ' on ' + column() + '.';
      showResult(r);
      setBusy(false);
    });
  }

  // The ranking as a list: each row shows its model's fit when clicked.
  function showRanking(doc, job) {
    var list = $('ranking');
    list.textContent = '';
    var rows = doc.columns[0].ranking;
    rows.forEach(function (r, i) {
      var li = document.createElement('li');
      li.tabIndex = 0;
      li.setAttribute('data-row', String(i + 1));
      var name = document.createElement('code');
      name.textContent = r.model;
      var facts = document.createElement('span');
      facts.className = 'facts';
      facts.textContent = ' WVIC ' + Number(r.criterion).toPrecision(5) +
        (r.gof_p_value !== null && r.gof_p_value !== undefined ? ', GoF p ' + Number(r.gof_p_value).toPrecision(2) : '');
      li.appendChild(name);
      li.appendChild(facts);
      if (i === 0) li.classList.add('active');
      var show = function () { showRow(job, i + 1, rows.length, li); };
      li.addEventListener('click', show);
      li.addEventListener('keydown', function (e) { if (e.key === 'Enter') show(); });
      list.appendChild(li);
    });
  }

  function showRow(job, row, rows, li) {
    showError('');
    status('row ' + row + ' of ' + rows + '…');
    api('GET', '/api/jobs/' + job + '/ranking/' + row).then(function (r) {
      document.querySelectorAll('#ranking li').forEach(function (x) { x.classList.remove('active'); });
      li.classList.add('active');
      showResult(r);
      status('ranking row ' + row + ' of ' + rows + ': ' + r.model +
        (row > 1 ? ' (as the selection fitted it, under its shared Omega; Fit it for intervals)' : ''));
      $('model').value = r.model;
      componentsFromModel();
    }).catch(function (e) { showError(e.message); });
  }

  function runSelect() {
    var body = baseBody();
    body.model = $('maximal').value.trim();
    $('ranking').textContent = '';
    runJob('/api/select', body, 'selection over ' + body.model, function (r, job) {
      state.document = r.document;
      state.selectJob = job;
      var best = r.document.columns[0].best;
      $('export-note').textContent = 'Exports the selection\u2019s chosen model' + (best ? ' ' + best : '') + '.';
      showResult(r);
      showRanking(r.document, job);
      setBusy(false);
    });
  }

  function overlayBody() {
    var o = { format: $('overlay-format').value };
    if ($('overlay-file').value) o.file = $('overlay-file').value;
    else o.text = $('overlay-text').value;
    return o;
  }

  function applyOverlay() {
    var o = overlayBody();
    var b = Object.assign({ dataset: state.dataset.dataset, column: column(), units: $('units').value.trim() }, o);
    showError('');
    api('POST', '/api/overlay', b).then(function (r) {
      state.overlay = o;
      $('overlay-model').textContent = r.name + ' = ' + r.model + '. ' + (r.conversions || []).join('; ');
      setBusy(false);
      rerun();
    }).catch(function (e) { showError(e.message); });
  }

  function clearOverlay() {
    state.overlay = null;
    $('overlay-model').textContent = '';
    setBusy(false);
    rerun();
  }

  // Runs the last request again (an overlay changes every plot).
  function rerun() {
    var r = state.lastRequest;
    if (r) runJob(r.endpoint, r.body, r.label, r.done);
  }

  function exportModel() {
    if (!state.document) return;
    var body = { result: state.document, format: $('export-format').value, units: $('units').value.trim() };
    showError('');
    api('POST', '/api/export', body).then(function (e) {
      $('export-preview').textContent = e.content;
      $('export-summary').textContent = e.filename + ' (' + $('export-format').value + ')';
      $('export-details').hidden = false;
      $('export-details').open = true;
      var blob = new Blob([e.content], { type: 'text/plain' });
      var a = document.createElement('a');
      a.href = URL.createObjectURL(blob);
      a.download = e.filename;
      document.body.appendChild(a);
      a.click();
      a.remove();
      setTimeout(function () { URL.revokeObjectURL(a.href); }, 1000);
      status('exported ' + e.filename + ((e.warnings || []).length ? ' (' + e.warnings.length + ' warning(s) in its header)' : ''));
    }).catch(function (e) { showError(e.message); });
  }

  function cancelJob() {
    if (!state.job) return;
    api('DELETE', '/api/jobs/' + state.job).catch(function (e) { showError(e.message); });
    status('cancelling…');
  }

  // ---- wiring ----

  $('open').addEventListener('click', openFile);
  $('upload').addEventListener('change', uploadFile);
  $('column').addEventListener('change', runWv);
  $('wv').addEventListener('click', runWv);
  $('fit').addEventListener('click', function () { runFit(); });
  $('select').addEventListener('click', runSelect);
  $('overlay').addEventListener('click', applyOverlay);
  $('overlay-clear').addEventListener('click', clearOverlay);
  $('export').addEventListener('click', exportModel);
  $('cancel').addEventListener('click', cancelJob);
  document.querySelectorAll('#components input, #ar1').forEach(function (c) {
    c.addEventListener('change', modelFromComponents);
  });
  $('model').addEventListener('input', componentsFromModel);
  $('model').addEventListener('keydown', function (e) { if (e.key === 'Enter' && state.dataset) runFit(); });
  setBusy(false);
  loadFiles();
})();
