(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('napkin-data').textContent);
  function esc(text) {
    return String(text).replace(/[&<>"']/g, function (c) {
      return { '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c];
    });
  }
  var componentColors = ['#1f77b4', '#d62728', '#2ca02c', '#222222'];
  var groupColors = ['#1f4e9c', '#d9730d', '#2a9d55', '#8e44ad', '#c0392b', '#16a085', '#7f8c8d'];
  var windowFill = ['rgba(230, 126, 34, 0.20)', 'rgba(52, 120, 200, 0.13)'];
  var windowInk = ['#b85c00', '#1f4e9c'];

  function drawn(element) {
    return function (graph, initial) { if (initial) element.setAttribute('data-drawn', 'true'); };
  }

  // What every chart over time shares: the time axis, the legend under the
  // plot, the grid and the axis label sizes.
  function timeAxes(element, chart) {
    return {
      labels: ['time (ms)'].concat(chart.labels),
      xlabel: 'time (ms)',
      ylabel: esc(chart.ylabel),
      legend: 'always',
      labelsDiv: element.parentNode.querySelector('.legend'),
      labelsSeparateLines: false,
      gridLineColor: '#e4e7eb',
      axisLabelFontSize: 12,
      xLabelHeight: 16,
      yLabelWidth: 16,
      axes: { y: { axisLabelWidth: 56 } }
    };
  }

  // The chart's samples as dygraphs rows: [t, y0, y1, ...].
  function timeRows(chart) {
    var rows = new Array(chart.t.length);
    for (var i = 0; i < chart.t.length; ++i) {
      var row = [chart.t[i]];
      for (var k = 0; k < chart.y.length; ++k) row.push(chart.y[k][i]);
      rows[i] = row;
    }
    return rows;
  }

  // The band between two traces as one polygon per run of rows where both exist.
  function shadeBetween(canvas, graph, chart, low, high) {
    var start = 0;
    while (start < chart.t.length) {
      while (start < chart.t.length && (chart.y[low][start] === null || chart.y[high][start] === null)) ++start;
      var end = start;
      while (end < chart.t.length && chart.y[low][end] !== null && chart.y[high][end] !== null) ++end;
      if (end - start > 1) {
        canvas.beginPath();
        for (var i = start; i < end; ++i) {
          var x = graph.toDomXCoord(chart.t[i]), y = graph.toDomYCoord(chart.y[high][i]);
          if (i === start) canvas.moveTo(x, y); else canvas.lineTo(x, y);
        }
        for (var j = end - 1; j >= start; --j)
          canvas.lineTo(graph.toDomXCoord(chart.t[j]), graph.toDomYCoord(chart.y[low][j]));
        canvas.closePath();
        canvas.fill();
      }
      start = end;
    }
  }

  // A chart with bands (a rating against a model: the test, the model, the
  // ISO/TS 18571 inner and outer corridors): the curves solid, each band's
  // bounds dashed in its colour with the band shaded.
  var bandColors = ['#2a9d55', '#d9730d'];
  function bandOptions(chart) {
    if (!chart.bands || chart.bands.length === 0) return {};
    var colors = componentColors.slice(0, chart.labels.length), series = {};
    chart.bands.forEach(function (band, b) {
      band.forEach(function (k) {
        colors[k] = bandColors[b % bandColors.length];
        series[chart.labels[k]] = { strokeWidth: 1, strokePattern: [5, 3] };
      });
    });
    return { colors: colors, series: series };
  }

  function timeHistory(chart) {
    var element = document.getElementById(chart.id);
    var rows = timeRows(chart);
    new Dygraph(element, rows, Object.assign(timeAxes(element, chart), {
      colors: chart.labels.length === 1 ? ['#1f4e9c'] : componentColors.slice(0, chart.labels.length),
      strokeWidth: 1.4
    }, bandOptions(chart), {
      underlayCallback: function (canvas, area, graph) {
        (chart.bands || []).forEach(function (band, b) {
          canvas.fillStyle = bandColors[b % bandColors.length];
          canvas.globalAlpha = 0.12;
          shadeBetween(canvas, graph, chart, band[0], band[1]);
          canvas.globalAlpha = 1;
        });
        chart.windows.forEach(function (w, i) {
          var x1 = graph.toDomXCoord(w.t1), x2 = graph.toDomXCoord(w.t2);
          canvas.fillStyle = windowFill[i % 2];
          canvas.fillRect(x1, area.y, x2 - x1, area.h);
          canvas.strokeStyle = windowInk[i % 2];
          canvas.lineWidth = 1;
          canvas.setLineDash([4, 3]);
          canvas.beginPath();
          canvas.moveTo(x1, area.y); canvas.lineTo(x1, area.y + area.h);
          canvas.moveTo(x2, area.y); canvas.lineTo(x2, area.y + area.h);
          canvas.stroke();
          canvas.setLineDash([]);
          canvas.font = 'bold 12px system-ui, sans-serif';
          canvas.fillStyle = windowInk[i % 2];
          var text = w.label + '  (' + w.t1.toFixed(1) + '–' + w.t2.toFixed(1) + ' ms)';
          var x = Math.max(area.x + 4, Math.min(x2 + 6, area.x + area.w - canvas.measureText(text).width - 4));
          canvas.fillText(text, x, area.y + 16 + 16 * i);
        });
      },
      drawCallback: drawn(element)
    }));
  }

  // Every test as a point (left of its group's tick), the group's mean with
  // its 95 % confidence interval as a bar (right of the tick).
  function distribution(chart) {
    var element = document.getElementById(chart.id);
    var groups = chart.groups;
    var rows = [];
    groups.forEach(function (group, g) {
      group.values.forEach(function (value, j) {
        var row = [g - 0.12 + ((j % 5) - 2) * 0.035];
        for (var k = 0; k < groups.length; ++k) row.push(k === g ? value : null);
        rows.push(row);
      });
    });
    rows.sort(function (a, b) { return a[0] - b[0]; });
    new Dygraph(element, rows, {
      labels: ['variant'].concat(groups.map(function (g) { return g.name; })),
      ylabel: esc(chart.ylabel),
      colors: groups.map(function (g, k) { return groupColors[k % groupColors.length]; }),
      strokeWidth: 0,
      drawPoints: true,
      pointSize: 3.5,
      highlightCircleSize: 5,
      legend: 'always',
      labelsDiv: element.parentNode.querySelector('.legend'),
      labelsSeparateLines: false,
      gridLineColor: '#e4e7eb',
      axisLabelFontSize: 12,
      yLabelWidth: 16,
      includeZero: true,
      dateWindow: [-0.5, groups.length - 0.5],
      interactionModel: {},
      axes: {
        x: {
          drawGrid: false,
          axisLabelWidth: 120,
          ticker: function () { return groups.map(function (g, k) { return { v: k, label: esc(g.name) }; }); },
          valueFormatter: function (x) { var k = Math.round(x); return k >= 0 && k < groups.length ? esc(groups[k].name) : ''; }
        },
        y: { axisLabelWidth: 56 }
      },
      underlayCallback: function (canvas, area, graph) {
        groups.forEach(function (group, k) {
          var x = graph.toDomXCoord(k + 0.18);
          var ink = groupColors[k % groupColors.length];
          canvas.strokeStyle = ink;
          canvas.fillStyle = ink;
          canvas.lineWidth = 2;
          if (group.ci_low !== null && group.ci_high !== null) {
            var top = graph.toDomYCoord(group.ci_high), bottom = graph.toDomYCoord(group.ci_low);
            canvas.beginPath();
            canvas.moveTo(x, top); canvas.lineTo(x, bottom);
            canvas.moveTo(x - 6, top); canvas.lineTo(x + 6, top);
            canvas.moveTo(x - 6, bottom); canvas.lineTo(x + 6, bottom);
            canvas.stroke();
          }
          var y = graph.toDomYCoord(group.mean);
          canvas.fillRect(x - 10, y - 1.5, 20, 3);
        });
      },
      drawCallback: drawn(element)
    });
  }

  // Every test of a series thin in its variant's colour, each variant's
  // mean ± 1 sd corridor as two dashed bounds with the band between them
  // shaded (null values: gaps).
  function overlay(chart) {
    var element = document.getElementById(chart.id);
    var rows = timeRows(chart);
    var series = {};
    var colors = chart.labels.map(function (label, k) {
      var ink = groupColors[chart.group[k] % groupColors.length];
      series[label] = chart.kind[k] === 'test'
        ? { strokeWidth: 0.9 }
        : { strokeWidth: 1.6, strokePattern: [6, 3] };
      return ink;
    });
    // The legend: one entry per variant (its tests' line and its corridor's
    // dash), not one per test; hovering a trace names its test and value.
    var counts = chart.groups.map(function () { return 0; });
    chart.kind.forEach(function (kind, k) { if (kind === 'test') ++counts[chart.group[k]]; });
    function legend(data) {
      var html = chart.groups.map(function (name, g) {
        var ink = groupColors[g % groupColors.length];
        return '<span class="variant-legend" data-variant="' + esc(name) + '">' +
          '<span class="swatch" style="border-top: 2px solid ' + ink + '"></span>' + esc(name) +
          ' (' + counts[g] + (counts[g] === 1 ? ' test' : ' tests') + ')' +
          ' <span class="swatch" style="border-top: 2px dashed ' + ink + '"></span>mean ± 1 sd</span>';
      }).join(' ');
      if (data.x !== undefined && data.x !== null) {
        data.series.forEach(function (entry) {
          if (!entry.isHighlighted) return;
          html += ' <span class="hover-test">' + entry.labelHTML + ' at ' + data.xHTML + ' ms: ' +
            (entry.yHTML === undefined ? '—' : entry.yHTML) + '</span>';
        });
      }
      return html;
    }
    new Dygraph(element, rows, Object.assign(timeAxes(element, chart), {
      colors: colors,
      series: series,
      legendFormatter: legend,
      highlightSeriesOpts: { strokeWidth: 2.2, highlightCircleSize: 3 },
      underlayCallback: function (canvas, area, graph) {
        chart.groups.forEach(function (name, g) {
          var low = -1, high = -1;
          chart.kind.forEach(function (kind, k) {
            if (chart.group[k] !== g) return;
            if (kind === 'low') low = k;
            if (kind === 'high') high = k;
          });
          if (low < 0 || high < 0) return;
          canvas.fillStyle = groupColors[g % groupColors.length];
          canvas.globalAlpha = 0.13;
          shadeBetween(canvas, graph, chart, low, high);
          canvas.globalAlpha = 1;
        });
      },
      drawCallback: drawn(element)
    }));
  }

  // The verdict as a picture (formats/report_verdict_plots.h): the forest
  // plot of the changes against the baseline, and a strip of every test's
  // value per limited criterion.
  var outcomeInks = {
    2: ['#2a9d55', '#c0392b'],
    3: ['#2a9d55', '#d4a000', '#c0392b'],
    4: ['#2a9d55', '#d4b000', '#e67e22', '#c0392b']
  };
  function inksFor(count) {
    if (outcomeInks[count]) return outcomeInks[count];
    var inks = [];
    for (var k = 0; k < count; ++k) inks.push(groupColors[k % groupColors.length]);
    return inks;
  }
  function dot(ink) {
    return '<span class="dot" style="background: ' + ink + '"></span>';
  }
  // What the forest and the strips share: points only, one series per kind
  // (`names`, coloured by `inks`), a legend of the kinds that `describe`
  // (the hovered row's index) extends, no zoom, and `more` options.
  function pointPlot(element, xName, names, inks, describe, more) {
    function legend(info) {
      var html = names.map(function (name, k) {
        return '<span class="variant-legend">' + dot(inks[k]) + esc(name) + '</span>';
      }).join(' ');
      var selected = info.dygraph.getSelection();
      return selected >= 0 ? html + describe(selected) : html;
    }
    return Object.assign({
      labels: [xName].concat(names),
      colors: inks,
      strokeWidth: 0,
      drawPoints: true,
      highlightCircleSize: 6,
      legend: 'always',
      legendFormatter: legend,
      labelsDiv: element.parentNode.querySelector('.legend'),
      gridLineColor: '#e4e7eb',
      axisLabelFontSize: 12,
      interactionModel: {},
      drawCallback: drawn(element)
    }, more);
  }
  var forestKinds = ['significant change (p < 0.05)', 'equivalent within the margin', 'neither shown'];
  var forestInks = ['#c0392b', '#2a9d55', '#5b6470'];
  var ratioTicks = [0.1, 0.2, 0.25, 0.33, 0.5, 0.67, 0.8, 0.9, 1, 1.1, 1.25, 1.5, 2, 3, 4, 5, 10];

  function forest(chart) {
    var element = document.getElementById(chart.id);
    var n = chart.rows.length;
    var low = 1 - chart.margin, high = 1 + chart.margin;
    chart.rows.forEach(function (row) {
      low = Math.min(low, row.low !== null ? row.low : row.ratio, row.ratio);
      high = Math.max(high, row.high !== null ? row.high : row.ratio, row.ratio);
    });
    var pad = Math.pow(high / low, 0.06);
    function kindOf(row) { return row.significant ? 0 : (row.equivalent ? 1 : 2); }
    var data = chart.rows.map(function (row, k) {
      var out = [row.ratio, null, null, null];
      out[1 + kindOf(row)] = n - k;  // the first row on top
      return { values: out, row: row };
    });
    data.sort(function (a, b) { return a.values[0] - b.values[0]; });
    function describe(selected) {
      if (selected >= data.length) return '';
      var row = data[selected].row;
      return ' <span class="hover-test">' + esc(row.label) + ': ratio ' + row.ratio.toFixed(3) +
        (row.low !== null ? ' [' + row.low.toFixed(3) + ', ' + row.high.toFixed(3) + ']' : ' (no interval)') +
        '</span>';
    }
    new Dygraph(element, data.map(function (d) { return d.values; }), pointPlot(element, 'ratio', forestKinds, forestInks, describe, {
      pointSize: 5,
      xlabel: 'ratio to ' + esc(chart.baseline) + ' (log axis)',
      xLabelHeight: 16,
      dateWindow: [low / pad, high * pad],
      valueRange: [0.4, n + 0.6],
      axes: {
        x: {
          logscale: true,
          // The ratios of ratioTicks within the axis, each at least 38 px from the others (1 always).
          ticker: function (min, max, pixels) {
            function at(v) { return Math.log(v / min) / Math.log(max / min) * pixels; }
            var shown = ratioTicks.filter(function (v) { return v >= min && v <= max; });
            var kept = shown.filter(function (v) { return v === 1; });
            shown.forEach(function (v) {
              if (kept.every(function (k) { return Math.abs(at(v) - at(k)) >= 38; })) kept.push(v);
            });
            kept.sort(function (a, b) { return a - b; });
            return kept.map(function (v) { return { v: v, label: String(v) }; });
          }
        },
        y: {
          drawGrid: false,
          axisLabelWidth: 190,
          ticker: function () {
            return chart.rows.map(function (row, k) { return { v: n - k, label: esc(row.label) }; });
          }
        }
      },
      underlayCallback: function (canvas, area, graph) {
        // dygraphs' toDomXCoord is linear whatever the axis: the log axis's place from toPercentXCoord.
        function domX(x) { return area.x + graph.toPercentXCoord(x) * area.w; }
        var x1 = domX(1 - chart.margin), x2 = domX(1 + chart.margin);
        canvas.fillStyle = 'rgba(42, 157, 85, 0.13)';
        canvas.fillRect(x1, area.y, x2 - x1, area.h);
        var one = domX(1);
        canvas.strokeStyle = '#222';
        canvas.lineWidth = 1.2;
        canvas.beginPath();
        canvas.moveTo(one, area.y); canvas.lineTo(one, area.y + area.h);
        canvas.stroke();
        chart.rows.forEach(function (row, k) {
          if (row.low === null) return;
          var y = graph.toDomYCoord(n - k);
          var a = domX(row.low), b = domX(row.high);
          canvas.strokeStyle = forestInks[kindOf(row)];
          canvas.lineWidth = 2;
          canvas.beginPath();
          canvas.moveTo(a, y); canvas.lineTo(b, y);
          canvas.moveTo(a, y - 5); canvas.lineTo(a, y + 5);
          canvas.moveTo(b, y - 5); canvas.lineTo(b, y + 5);
          canvas.stroke();
        });
      }
    }));
  }

  // Every test's value (a point per test, its variant's column) against the
  // limit's edges, each class's zone shaded and each point in its class's
  // colour: best green, worst red.
  function strip(chart) {
    var element = document.getElementById(chart.id);
    var groups = chart.groups, classes = chart.classes, inks = inksFor(classes.length);
    var seen = groups.map(function () { return 0; });
    var data = chart.points.map(function (point) {
      var j = seen[point[0]]++;
      var values = [point[0] + ((j % 7) - 3) * 0.045];
      for (var k = 0; k < classes.length; ++k) values.push(k === point[2] ? point[1] : null);
      return { values: values, test: point[3], value: point[1], category: point[2] };
    });
    data.sort(function (a, b) { return a.values[0] - b.values[0]; });
    var lo = Infinity, hi = -Infinity;
    chart.points.forEach(function (point) { lo = Math.min(lo, point[1]); hi = Math.max(hi, point[1]); });
    chart.edges.forEach(function (edge) { lo = Math.min(lo, edge.value); hi = Math.max(hi, edge.value); });
    var span = hi > lo ? hi - lo : Math.abs(hi) || 1;
    function describe(selected) {
      if (selected >= data.length) return '';
      var d = data[selected];
      return ' <span class="hover-test">' + esc(d.test) + ': ' + d.value.toPrecision(4) + ' (' +
        esc(classes[d.category]) + ')</span>';
    }
    new Dygraph(element, data.map(function (d) { return d.values; }), pointPlot(element, 'variant', classes, inks, describe, {
      pointSize: 4,
      ylabel: esc(chart.ylabel),
      yLabelWidth: 16,
      dateWindow: [-0.5, groups.length - 0.5],
      valueRange: [lo - 0.12 * span, hi + 0.12 * span],
      axes: {
        x: {
          drawGrid: false,
          axisLabelWidth: 120,
          ticker: function () { return groups.map(function (g, k) { return { v: k, label: esc(g) }; }); },
          valueFormatter: function (x) { var k = Math.round(x); return k >= 0 && k < groups.length ? esc(groups[k]) : ''; }
        },
        y: { axisLabelWidth: 56 }
      },
      underlayCallback: function (canvas, area, graph) {
        var bottom = area.y + area.h, top = area.y;
        for (var i = 0; i <= chart.edges.length; ++i) {
          var from = i === 0 ? bottom : graph.toDomYCoord(chart.edges[i - 1].value);
          var to = i === chart.edges.length ? top : graph.toDomYCoord(chart.edges[i].value);
          canvas.fillStyle = inks[Math.min(i, inks.length - 1)];
          canvas.globalAlpha = 0.09;
          canvas.fillRect(area.x, Math.min(from, to), area.w, Math.abs(from - to));
          canvas.globalAlpha = 1;
        }
        canvas.font = '11px system-ui, sans-serif';
        chart.edges.forEach(function (edge, i) {
          var y = graph.toDomYCoord(edge.value);
          canvas.strokeStyle = inks[Math.min(i + 1, inks.length - 1)];
          canvas.lineWidth = 1.4;
          canvas.setLineDash([6, 3]);
          canvas.beginPath();
          canvas.moveTo(area.x, y); canvas.lineTo(area.x + area.w, y);
          canvas.stroke();
          canvas.setLineDash([]);
          canvas.fillStyle = '#333';
          var width = canvas.measureText(edge.label).width;
          canvas.fillText(edge.label, area.x + area.w - width - 4, y - 3);
        });
      }
    }));
  }

  function guarded(draw) {
    return function (chart) {
      try { draw(chart); } catch (e) { window.napkinReportError(chart.id + ': ' + (e && e.message ? e.message : e)); }
    };
  }
  data.charts.forEach(guarded(timeHistory));
  data.distributions.forEach(guarded(distribution));
  data.overlays.forEach(guarded(overlay));
  (data.verdict_plots || []).forEach(guarded(function (chart) {
    if (chart.kind === 'forest') forest(chart); else strip(chart);
  }));
})();
