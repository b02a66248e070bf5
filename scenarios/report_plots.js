// The plots of beadtwin's report.html and sweep.html, drawn with Chart.js (embedded in the report before
// this script). The report carries each plot's data as JSON in a script element of class beadtwin-plot
// (type application/json); this script puts a canvas after each one and draws it. Kinds: "substrate" (the
// substrate temperature per layer against the temperature at which what was under the beads would carry
// them, and T_g), "layer_time" (each layer's time
// against the layer times that would have put it in the fusion window), "history" (chosen layers' mean
// temperature against time) and "pareto" (a sweep's variants by two metrics). Missing values are null and
// leave gaps. Colours for verdicts come with the data, from the same table the pictures use.
(function () {
  'use strict';
  const seriesColours = ['#1f77b4', '#e07b00', '#2ca02c', '#9467bd', '#8c564b', '#d62728', '#17becf',
                         '#7f7f7f'];
  const fmt = (v, digits) => (v === null || v === undefined ? '–' : v.toFixed(digits));

  // A horizontal line across the layers of a category axis, for a limit.
  function level(label, value, count, colour, dash, fill) {
    return {
      type: 'line', label: label, data: new Array(count).fill(value), borderColor: colour,
      borderDash: dash, borderWidth: 1.5, pointRadius: 0, pointHitRadius: 0, fill: fill || false,
      backgroundColor: colour + '14', order: 0,
    };
  }

  function axes(x, y, yOptions) {
    return {x: {title: {display: true, text: x}}, y: Object.assign({title: {display: true, text: y}}, yOptions)};
  }

  function substrate(p) {
    const n = p.layers.length;
    const colours = p.colours;
    const datasets = [
      {type: 'line', label: 'mean', data: p.mean, borderColor: '#333', borderWidth: 1.5, pointRadius: 2, pointStyle: 'circle',
       pointBackgroundColor: colours, pointBorderColor: colours, spanGaps: false, order: 1},
      {type: 'bar', label: 'least to most', data: p.min.map((lo, i) => (lo === null ? null : [lo, p.max[i]])),
       backgroundColor: colours.map((c) => c + '99'), borderColor: colours, borderWidth: 1,
       barPercentage: 1.0, categoryPercentage: 0.6, order: 2},
      {type: 'line', label: 'carries the bead up to (mean; above: slumps)', data: p.support,
       borderColor: p.hot_colour, borderDash: [4, 3], borderWidth: 1.5, pointRadius: 0, pointHitRadius: 0,
       stepped: 'middle', spanGaps: false, fill: false, order: 0},
      level('T_g ' + p.tg.toFixed(0) + ' °C', p.tg, n, '#555', [2, 3]),
    ];
    return {
      type: 'bar',
      data: {labels: p.layers, datasets: datasets},
      options: {
        scales: axes('layer', 'substrate °C at deposition', {beginAtZero: false}),
        plugins: {tooltip: {callbacks: {
          title: (items) => 'layer ' + p.layers[items[0].dataIndex] + ': ' + p.verdicts[items[0].dataIndex],
          label: (item) => {
            const i = item.dataIndex;
            if (item.datasetIndex > 1) return item.dataset.label;
            return 'least / mean / most ' + fmt(p.min[i], 1) + ' / ' + fmt(p.mean[i], 1) + ' / ' +
                   fmt(p.max[i], 1) + ' °C';
          },
        }}},
      },
    };
  }

  function layerTime(p) {
    const colours = p.colours;
    // A window unbounded above runs to the top of the plot.
    const known = (a) => a.filter((v) => v !== null);
    const ends = (bands) => known(bands).map((b) => b[1]).filter((v) => v !== null);
    const top = 1.1 * Math.max(0, ...known(p.duration), ...ends(p.window), ...ends(p.typical));
    const band = (bands) => bands.map((b) => (b === null ? null : [b[0], b[1] === null ? top : b[1]]));
    const green = (alpha) => 'rgba(46, 139, 87, ' + alpha + ')';
    return {
      type: 'bar',
      data: {labels: p.layers, datasets: [
        {label: 'layer time as printed', data: p.duration, backgroundColor: colours, barPercentage: 0.5,
         categoryPercentage: 1.0, grouped: false, order: 1},
        {label: 'window: all of the landing area', data: band(p.window), backgroundColor: green(0.35),
         barPercentage: 1.0, categoryPercentage: 1.0, grouped: false, order: 2},
        {label: 'window: half of it (typical)', data: band(p.typical), backgroundColor: green(0.15),
         barPercentage: 1.0, categoryPercentage: 1.0, grouped: false, order: 3},
      ]},
      options: {
        scales: axes('layer', 'layer time, s'),
        plugins: {tooltip: {callbacks: {
          title: (items) => 'layer ' + p.layers[items[0].dataIndex] + ': ' + p.verdicts[items[0].dataIndex],
          label: (item) => {
            const i = item.dataIndex;
            if (item.datasetIndex === 0) return 'printed in ' + fmt(p.duration[i], 1) + ' s';
            return item.dataset.label + ': ' + (item.datasetIndex === 1 ? p.window_text : p.typical_text)[i] +
                   ' s';
          },
        }}},
      },
    };
  }

  function history(p) {
    const t0 = p.times[0], t1 = p.times[p.times.length - 1];
    const line = (label, value, colour, dash) => ({
      label: label, data: [{x: t0, y: value}, {x: t1, y: value}], borderColor: colour, borderDash: dash,
      borderWidth: 1.5, pointRadius: 0, pointHitRadius: 0,
    });
    const datasets = p.series.map((s, k) => ({
      label: s.label, data: s.temp.map((y, i) => ({x: p.times[i], y: y})),
      borderColor: seriesColours[k % seriesColours.length], borderWidth: 1.5, pointRadius: 0,
      spanGaps: false,
    }));
    if (p.support !== null) {
      datasets.push(line('carries the bead up to ' + p.support.toFixed(0) + ' °C (median layer)', p.support,
                         p.hot_colour, [4, 3]));
    }
    datasets.push(line('T_g ' + p.tg.toFixed(0) + ' °C', p.tg, '#555', [2, 3]));
    return {
      type: 'line',
      data: {datasets: datasets},
      options: {
        parsing: true,
        scales: {
          x: {type: 'linear', min: t0, max: t1, title: {display: true, text: 'time, ' + p.unit}},
          y: {title: {display: true, text: 'layer mean °C'}},
        },
        interaction: {mode: 'nearest', axis: 'x', intersect: false},
        plugins: {tooltip: {callbacks: {
          title: (items) => fmt(items[0].parsed.x, 1) + ' ' + p.unit,
          label: (item) => item.dataset.label + ': ' + fmt(item.parsed.y, 1) + ' °C',
        }}},
      },
    };
  }

  // A sweep's variants by two metrics (sweep.html): every variant that ran as a point (a red cross where a
  // gate failed, on the front too), the Pareto front joined by a line, each point named in its tooltip.
  function pareto(p) {
    const point = (v) => ({x: v.x, y: v.y, name: v.name});
    const passed = p.points.filter((v) => v.passed).map(point);
    const failed = p.points.filter((v) => !v.passed).map(point);
    const front = p.front.map(point);
    return {
      type: 'scatter',
      data: {datasets: [
        {label: 'Pareto front', type: 'line', data: front, borderColor: '#1f77b4', backgroundColor: '#1f77b4',
         borderWidth: 2, pointRadius: 5, pointStyle: 'circle', order: 0},
        {label: 'variants that pass their gates', data: passed, borderColor: '#2e8b57',
         backgroundColor: '#2e8b5799', pointRadius: 4, pointStyle: 'circle', order: 1},
        {label: 'variants that fail a gate', data: failed, borderColor: '#c0392b', backgroundColor: '#c0392b99',
         pointRadius: 6, pointStyle: 'crossRot', borderWidth: 2, order: -1},
      ]},
      options: {
        scales: axes(p.x_label, p.y_label, {}),
        plugins: {
          // In the datasets' order, whatever order they are drawn in.
          legend: {labels: {usePointStyle: true, sort: (a, b) => a.datasetIndex - b.datasetIndex}},
          tooltip: {callbacks: {
            label: (item) => item.raw.name + ': ' + fmt(item.parsed.x, p.x_digits) + ', ' +
                             fmt(item.parsed.y, p.y_digits),
          }},
        },
      },
    };
  }

  const kinds = {substrate: substrate, layer_time: layerTime, history: history, pareto: pareto};
  for (const holder of document.querySelectorAll('script.beadtwin-plot')) {
    const p = JSON.parse(holder.textContent);
    const config = kinds[p.kind](p);
    config.options = Object.assign({animation: false, responsive: true, maintainAspectRatio: false},
                                   config.options);
    // Lines show in the legend as lines, bars as boxes.
    config.options.plugins = Object.assign({legend: {labels: {usePointStyle: true}}}, config.options.plugins);
    for (const d of config.data.datasets) {
      if (!d.pointStyle) d.pointStyle = (d.type || config.type) === 'line' ? 'line' : 'rect';
    }
    const box = document.createElement('div');
    box.className = 'plot';
    const canvas = document.createElement('canvas');
    canvas.setAttribute('role', 'img');
    canvas.setAttribute('aria-label', p.label);
    box.appendChild(canvas);
    holder.after(box);
    new Chart(canvas, config);
  }
})();
