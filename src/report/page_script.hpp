#pragma once
// The page's own script: draws every figure spec of the report-data block with Chart.js (no
// plotting code of ours: Chart.js draws, this only configures it), then sets
// document.documentElement.dataset.reportReady = "true". A chart that throws leaves the page
// not ready and its message in dataset.reportError. Internal to src/report.

namespace hrgbench::report::internal {

inline constexpr const char* kPageScript = R"JS(
(function () {
  "use strict";
  var root = document.documentElement;
  var data = JSON.parse(document.getElementById("report-data").textContent);
  var palette = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
                 "#7f7f7f"];
  var failed = [];
  data.figures.forEach(function (f) {
    var canvas = document.querySelector('canvas[data-figure="' + f.name + '"]');
    if (!canvas) return;
    try {
      var base = [];
      var colour = function (label) {
        var key = label.replace(/ model$/, "");
        var i = base.indexOf(key);
        if (i < 0) { base.push(key); i = base.length - 1; }
        return palette[i % palette.length];
      };
      // Log axes: "1e-7", "2e-7", "5e-7" (Chart.js's default writes every digit).
      var logTick = function (value) {
        if (!(value > 0)) return "";
        var e = Math.floor(Math.log10(value) + 1e-9);
        var m = Math.round(value / Math.pow(10, e));
        if (m !== 1 && m !== 2 && m !== 5) return "";
        return e >= -2 && e <= 3 ? String(Number((m * Math.pow(10, e)).toPrecision(1))) : m + "e" + e;
      };
      var yScale = function () {
        var y = { type: f.y_log ? "logarithmic" : "linear", title: { display: true, text: f.y_label } };
        if (f.y_log) y.ticks = { callback: logTick };
        return y;
      };
      // Legend entries drawn like their lines: a model's dashed, the data's solid.
      // With usePointStyle Chart.js takes the point's style, not the line's: the dash is set here
      // from the dataset, and a 2 px line shows it.
      var legend = { labels: { boxWidth: 12, usePointStyle: true, pointStyleWidth: 36,
        generateLabels: function (chart) {
          return Chart.defaults.plugins.legend.labels.generateLabels(chart).map(function (l) {
            var dataset = chart.data.datasets[l.datasetIndex];
            l.lineDash = dataset && dataset.borderDash ? dataset.borderDash : [];
            l.lineWidth = 2;
            return l;
          });
        } } };
      var config;
      if (f.type === "bar") {
        config = {
          type: "bar",
          data: {
            labels: f.labels,
            datasets: f.series.map(function (s) {
              return { label: s.label, data: s.y, backgroundColor: colour(s.label + (s.model ? "#" : "")) };
            })
          },
          options: {
            animation: false, responsive: false,
            scales: {
              x: { title: { display: true, text: f.x_label } },
              y: yScale()
            }
          }
        };
      } else {
        var datasets = f.series.map(function (s) {
          var xs = s.x || f.x;
          var points = new Array(s.y.length);
          for (var k = 0; k < s.y.length; ++k) points[k] = { x: xs[k], y: s.y[k] };
          return {
            label: s.label, data: points, borderColor: colour(s.label),
            backgroundColor: colour(s.label), borderDash: s.model ? [6, 3] : [],
            borderWidth: s.model ? 1.5 : 1, pointRadius: s.points ? 3 : 0, pointStyle: "line",
            showLine: true, spanGaps: false, yAxisID: s.axis === "y2" ? "y2" : "y"
          };
        });
        var scales = {
          x: { type: f.x_log ? "logarithmic" : "linear", title: { display: true, text: f.x_label } },
          y: yScale()
        };
        if (f.x_log) scales.x.ticks = { callback: logTick };
        if (f.series.some(function (s) { return s.axis === "y2"; })) {
          scales.y2 = { type: "linear", position: "right", grid: { drawOnChartArea: false },
                        title: { display: true, text: f.y2_label } };
        }
        if (f.equal_aspect) {
          scales.x.min = -1.1; scales.x.max = 1.1; scales.y.min = -1.1; scales.y.max = 1.1;
          legend.position = "bottom";
        }
        config = {
          type: "scatter",
          data: { datasets: datasets },
          options: {
            animation: false, responsive: false, parsing: false, normalized: true,
            aspectRatio: f.equal_aspect ? 1 : undefined,
            scales: scales, plugins: { legend: legend }
          }
        };
      }
      var chart = new Chart(canvas, config);
      if (f.equal_aspect) {
        // Equal scales on both axes need a square plot area: the legend and the tick labels take
        // their own room, so pad the longer side once it is known and draw again.
        // Padding the sides narrows the legend, which may wrap: a few rounds settle it.
        var side = 0, ends = 0, area = chart.chartArea;
        for (var round = 0; round < 4 && Math.abs(area.width - area.height) >= 1; ++round) {
          var excess = area.width - area.height;
          if (excess > 0) side += excess / 2; else ends -= excess / 2;
          if (side > 0 && ends > 0) { var common = Math.min(side, ends); side -= common; ends -= common; }
          chart.options.layout.padding = { left: side, right: side, top: ends, bottom: ends };
          chart.update();
          area = chart.chartArea;
        }
        canvas.dataset.plotArea = Math.round(area.width) + "x" + Math.round(area.height);
      }
      canvas.dataset.drawn = "true";
    } catch (e) {
      failed.push(f.name + ": " + e);
    }
  });
  if (failed.length) {
    root.dataset.reportError = failed.join("; ");
  } else {
    root.dataset.reportReady = "true";
  }
})();
)JS";

}  // namespace hrgbench::report::internal
