// plumb report: draws every chart listed in the page's data with Chart.js (inlined above),
// adds drag-to-zoom and double-click reset to each, and runs the animation flipbooks.
// window.plumbReport.ready is true once every chart has been drawn (tests wait for it).
(function () {
  'use strict';
  const report = { ready: false, charts: [] };
  window.plumbReport = report;

  function scale(axis) {
    const s = { type: axis.log ? 'logarithmic' : 'linear',
                title: { display: true, text: axis.label } };
    if (axis.log) s.ticks = { callback: (v) => Number(v).toPrecision(2) };
    return s;
  }

  function dataset(series) {
    const d = { label: series.label, data: series.points, borderColor: series.color,
                backgroundColor: series.color, borderWidth: series.width || 1.5,
                pointRadius: series.style === 'points' ? (series.radius || 3) : 0,
                pointHoverRadius: 5, showLine: series.style !== 'points',
                pointStyle: series.marker || 'circle' };
    if (series.dashed) d.borderDash = [6, 4];
    return d;
  }

  // Drag across a chart to zoom into that range; double-click to see everything again.
  function addZoom(chart, canvas, spec) {
    let start = null;
    const box = document.createElement('div');
    box.style.cssText = 'position:absolute;background:rgba(9,105,218,.15);display:none;pointer-events:none';
    canvas.parentNode.style.position = 'relative';
    canvas.parentNode.appendChild(box);
    canvas.addEventListener('mousedown', (e) => { start = { x: e.offsetX, y: e.offsetY }; });
    canvas.addEventListener('mousemove', (e) => {
      if (!start) return;
      box.style.display = 'block';
      box.style.left = Math.min(start.x, e.offsetX) + canvas.offsetLeft + 'px';
      box.style.top = Math.min(start.y, e.offsetY) + canvas.offsetTop + 'px';
      box.style.width = Math.abs(e.offsetX - start.x) + 'px';
      box.style.height = Math.abs(e.offsetY - start.y) + 'px';
    });
    canvas.addEventListener('mouseup', (e) => {
      box.style.display = 'none';
      if (!start) return;
      const s = start; start = null;
      if (Math.abs(e.offsetX - s.x) < 5 || spec.kind === 'bar') return;
      const x = chart.scales.x, y = chart.scales.y;
      chart.options.scales.x.min = x.getValueForPixel(Math.min(s.x, e.offsetX));
      chart.options.scales.x.max = x.getValueForPixel(Math.max(s.x, e.offsetX));
      if (Math.abs(e.offsetY - s.y) >= 5) {
        chart.options.scales.y.min = y.getValueForPixel(Math.max(s.y, e.offsetY));
        chart.options.scales.y.max = y.getValueForPixel(Math.min(s.y, e.offsetY));
      }
      chart.update('none');
    });
    canvas.addEventListener('dblclick', () => {
      for (const k of ['x', 'y']) { delete chart.options.scales[k].min; delete chart.options.scales[k].max; }
      chart.update('none');
    });
  }

  function draw(spec) {
    const canvas = document.getElementById(spec.id);
    let config;
    if (spec.kind === 'bar') {
      config = { type: 'bar',
                 data: { labels: spec.labels,
                         datasets: spec.series.map((s) => ({ label: s.label, data: s.values,
                           backgroundColor: s.color, borderColor: s.color, borderWidth: 1,
                           barPercentage: 1.0, categoryPercentage: 1.0 })) },
                 options: { animation: false, responsive: true, maintainAspectRatio: false,
                            scales: { x: { stacked: true, title: { display: true, text: spec.x.label } },
                                      y: { stacked: true, title: { display: true, text: spec.y.label } } } } };
    } else {
      config = { type: 'scatter', data: { datasets: spec.series.map(dataset) },
                 // neither `normalized` nor `parsing: false`: each tells Chart.js 3.9 that a dataset
                 // is sorted by x, and a scatter or a phase portrait is not (its x axis then ran from
                 // the first point to the last and cut the others off); parsed, it finds out
                 options: { animation: false, responsive: true, maintainAspectRatio: false,
                            interaction: { mode: 'nearest', intersect: false },
                            scales: { x: scale(spec.x), y: scale(spec.y) },
                            plugins: { tooltip: { callbacks: { label: (c) =>
                              `${c.dataset.label}: (${Number(c.parsed.x).toPrecision(6)}, ${Number(c.parsed.y).toPrecision(6)})` } } } } };
    }
    const chart = new Chart(canvas.getContext('2d'), config);
    addZoom(chart, canvas, spec);
    report.charts.push(chart);
  }

  function flipbook(node) {
    const frames = JSON.parse(node.getAttribute('data-frames'));
    const img = node.querySelector('img');
    const interval = Number(node.getAttribute('data-interval')) || 100;
    let i = 0;
    setInterval(() => { i = (i + 1) % frames.length; img.src = frames[i]; }, interval);
  }

  function start() {
    const specs = JSON.parse(document.getElementById('plumb-charts').textContent);
    specs.forEach(draw);
    document.querySelectorAll('.flipbook').forEach(flipbook);
    report.ready = true;
  }
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
  else start();
})();
