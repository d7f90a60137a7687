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
              y: { type: f.y_log ? "logarithmic" : "linear", title: { display: true, text: f.y_label } }
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
            borderWidth: 1, pointRadius: 0, showLine: true, spanGaps: false
          };
        });
        var scales = {
          x: { type: "linear", title: { display: true, text: f.x_label } },
          y: { type: f.y_log ? "logarithmic" : "linear", title: { display: true, text: f.y_label } }
        };
        if (f.equal_aspect) {
          scales.x.min = -1.1; scales.x.max = 1.1; scales.y.min = -1.1; scales.y.max = 1.1;
        }
        config = {
          type: "scatter",
          data: { datasets: datasets },
          options: {
            animation: false, responsive: false, parsing: false, normalized: true,
            scales: scales, plugins: { legend: { labels: { boxWidth: 12 } } }
          }
        };
      }
      new Chart(canvas, config);
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
