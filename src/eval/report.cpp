// The self-contained HTML comparison report: PNG data URIs (stb_image_write), inline SVG plots,
// a few lines of inline JavaScript for the before/after slider. No network resources.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rtd/eval/compare.h"

namespace rtd::eval {

std::string encodePng(const Image& srgb) {
  std::vector<unsigned char> bytes(size_t(srgb.width) * srgb.height * 3);
  for (size_t i = 0; i < size_t(srgb.width) * srgb.height; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = srgb.pixels[i * srgb.channels + std::min(c, srgb.channels - 1)];
      bytes[i * 3 + c] = (unsigned char)std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f);
    }
  std::string png;
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size_t(size)); },
      &png, srgb.width, srgb.height, 3, bytes.data(), srgb.width * 3);
  return png;
}

namespace {

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

std::string dataUri(const Image& srgb) { return "data:image/png;base64," + base64(encodePng(srgb)); }

std::string esc(const std::string& s) {
  std::string o;
  for (char ch : s) {
    switch (ch) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += ch;
    }
  }
  return o;
}

std::string fmt(double v, const char* f = "%.4g") {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "-&infin;";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string metricFormat(const MetricInfo& m, double v) {
  const std::string key = m.key;
  if (key == "psnr") return fmt(v, "%.2f");
  if (key == "ssim" || key == "flip") return fmt(v, "%.4f");
  return fmt(v, "%.4g");
}

Image crop(const Image& img, int x0, int y0, int w, int h) {
  Image out(w, h, img.channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < img.channels; ++c) out.at(x, y, c) = img.at(x0 + x, y0 + y, c);
  return out;
}

const char* kPalette[] = {"#888888", "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                          "#8c564b", "#e377c2", "#17becf", "#bcbd22"};

/// One line chart of a metric over frames, one polyline per run, warm-up frames shaded.
std::string plotSvg(const Comparison& c, const MetricInfo& m) {
  const double W = 640, H = 244, left = 64, right = 12, top = 42, bottom = 34;
  double lo = INFINITY, hi = -INFINITY;
  int fmin = INT32_MAX, fmax = INT32_MIN;
  for (const auto& r : c.runs)
    for (const auto& f : r.metrics.frames) {
      fmin = std::min(fmin, f.number);
      fmax = std::max(fmax, f.number);
      const double v = f.*m.field;
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' class='plot' width='" << W << "' height='" << H << "' viewBox='0 0 " << W
    << ' ' << H << "' role='img' aria-label='" << esc(m.label) << " per frame'>";
  s << "<text x='" << left << "' y='16' class='pt'>" << esc(m.label) << " (" << esc(m.space) << ", "
    << (!m.ranked ? "information, not ranked" : m.higherIsBetter ? "higher is better" : "lower is better") << ")</text>";
  if (!(lo <= hi) || fmin > fmax) {
    s << "<text x='" << left << "' y='" << H / 2 << "'>no values</text></svg>";
    return s.str();
  }
  if (hi - lo < 1e-12) {
    const double pad = std::max(std::abs(hi) * 0.05, 1e-6);
    lo -= pad;
    hi += pad;
  } else {
    const double pad = 0.05 * (hi - lo);
    lo -= pad;
    hi += pad;
  }
  const double pw = W - left - right, ph = H - top - bottom;
  const auto X = [&](double f) { return left + (fmax > fmin ? (f - fmin) / double(fmax - fmin) : 0.5) * pw; };
  const auto Y = [&](double v) { return top + (1.0 - (v - lo) / (hi - lo)) * ph; };
  // Warm-up region.
  int lastWarm = INT32_MIN;
  for (const auto& f : c.runs.front().metrics.frames)
    if (f.warmup) lastWarm = std::max(lastWarm, f.number);
  if (lastWarm != INT32_MIN)
    s << "<rect x='" << left << "' y='" << top << "' width='" << std::max(0.0, X(lastWarm + 0.5) - left) << "' height='"
      << ph << "' fill='#f1ead9'/><text x='" << left + 4 << "' y='" << top + 12 << "' class='wl'>warm-up</text>";
  s << "<rect x='" << left << "' y='" << top << "' width='" << pw << "' height='" << ph
    << "' fill='none' stroke='#999'/>";
  for (int t = 0; t <= 4; ++t) {
    const double v = lo + (hi - lo) * t / 4.0, y = Y(v);
    s << "<line x1='" << left << "' x2='" << left + pw << "' y1='" << y << "' y2='" << y << "' stroke='#e4e4e4'/>"
      << "<text x='" << left - 6 << "' y='" << y + 4 << "' text-anchor='end' class='tk'>" << fmt(v, "%.4g") << "</text>";
  }
  for (int t = 0; t <= 4; ++t) {
    const double f = fmin + (fmax - fmin) * t / 4.0;
    s << "<text x='" << X(f) << "' y='" << top + ph + 16 << "' text-anchor='middle' class='tk'>" << fmt(f, "%.0f")
      << "</text>";
  }
  s << "<text x='" << left + pw / 2 << "' y='" << H - 2 << "' text-anchor='middle' class='tk'>frame</text>";
  double legendX = left;
  for (size_t k = 0; k < c.runs.size(); ++k) {
    const auto& r = c.runs[k];
    const char* col = kPalette[k % 10];
    std::ostringstream pts;
    int count = 0;
    for (const auto& f : r.metrics.frames) {
      const double v = f.*m.field;
      if (!std::isfinite(v)) continue;
      pts << X(f.number) << ',' << Y(v) << ' ';
      ++count;
    }
    if (count == 1) s << "<circle cx='" << pts.str().substr(0, pts.str().find(',')) << "' cy='" << Y(r.metrics.frames.back().*m.field) << "' r='3' fill='" << col << "'/>";
    s << "<polyline fill='none' stroke='" << col << "' stroke-width='1.6' points='" << pts.str() << "'/>";
    s << "<rect x='" << legendX << "' y='22' width='10' height='10' fill='" << col << "'/><text x='" << legendX + 13
      << "' y='31' class='tk'>" << esc(r.label) << "</text>";
    legendX += 22 + 7.0 * double(r.label.size());
  }
  s << "</svg>";
  return s.str();
}

const char* kStyle = R"(
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:24px;color:#222;background:#fff;max-width:1400px}
h1{font-size:24px;margin:0 0 6px} h2{font-size:19px;margin:28px 0 8px;border-bottom:1px solid #ddd;padding-bottom:4px}
.meta{color:#555;font-size:14px;line-height:1.5}
table{border-collapse:collapse;font-size:13px;margin:6px 0} th,td{border:1px solid #ccc;padding:3px 8px;text-align:right}
th{background:#f3f3f3} td.l,th.l{text-align:left} td.best{font-weight:bold;background:#e6f4e6}
.strip{display:flex;flex-wrap:wrap;gap:10px} figure{margin:0} figcaption{font-size:12px;color:#333;margin-top:2px}
img.px{image-rendering:pixelated;display:block;border:1px solid #bbb}
.cmp{position:relative;display:inline-block;line-height:0;border:1px solid #888}
.cmp img{image-rendering:pixelated;display:block;width:100%;height:auto}
.cmp .top{position:absolute;left:0;top:0;width:100%;height:100%}
.cmp .lab{position:absolute;top:6px;background:rgba(0,0,0,.6);color:#fff;font-size:12px;line-height:1.4;padding:1px 6px}
.ctl{margin:6px 0;font-size:14px} .ctl input[type=range]{width:420px;vertical-align:middle}
.plots{display:flex;flex-wrap:wrap;gap:8px} .pt{font-size:13px;font-weight:600} .tk{font-size:11px;fill:#444} .wl{font-size:11px;fill:#8a6d2b}
.note{font-size:13px;color:#444;max-width:980px}
)";

const char* kScript = R"(
(function(){
 var s=document.getElementById('sl'),a=document.getElementById('cmpA'),b=document.getElementById('cmpB'),
     sa=document.getElementById('selA'),sb=document.getElementById('selB'),la=document.getElementById('labA'),lb=document.getElementById('labB');
 function clip(){a.parentNode.style.clipPath='inset(0 '+(100-s.value)+'% 0 0)';}
 function pick(){a.src=document.getElementById('full-'+sa.value).src;b.src=document.getElementById('full-'+sb.value).src;
   la.textContent=sa.options[sa.selectedIndex].text;lb.textContent=sb.options[sb.selectedIndex].text;}
 s.addEventListener('input',clip);sa.addEventListener('change',pick);sb.addEventListener('change',pick);pick();clip();
})();
)";

}  // namespace

std::string comparisonHtml(const Comparison& c) {
  const auto& metrics = metricList();
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><title>" << esc(c.title) << "</title><style>"
    << kStyle << "</style></head><body>\n";
  h << "<h1>" << esc(c.title) << "</h1>\n<div class='meta'>Source: " << esc(c.source) << "<br>" << c.width << "&times;"
    << c.height << ", " << c.frames << " frames, first " << c.eval.warmupFrames
    << " frame(s) are warm-up (averaged separately). Tone map for the display-referred metrics: "
    << esc(operatorName(c.eval.toneMap.op)) << ", exposure " << fmt(c.eval.toneMap.exposure, "%.2f")
    << " stops, then sRGB encoding. FLIP at " << fmt(c.eval.flip.pixelsPerDegree(), "%.1f")
    << " pixels per degree.<br>Machine: " << esc(c.machine) << ". Total time " << fmt(c.seconds, "%.1f")
    << " s (denoising and evaluation).";
  for (const auto& note : c.skipped) h << "<br>Skipped: " << esc(note);
  h << "</div>\n";

  // Summary tables: steady state, then warm-up.
  const auto summaryTableHtml = [&](bool warmup) {
    h << "<table><tr><th class='l'>run</th><th>frames</th>";
    for (const auto& m : metrics) h << "<th title='" << esc(m.space) << "'>" << esc(m.label) << "</th>";
    if (!warmup) h << "<th>median ms/frame</th>";
    h << "</tr>\n";
    std::vector<double> best(metrics.size(), NAN);
    for (size_t k = 0; k < metrics.size(); ++k) {
      if (!metrics[k].ranked) continue;  // information only: a frozen image has no temporal change
      for (const auto& r : c.runs) {
        const double v = (warmup ? r.metrics.warmup : r.metrics.steady).mean.*metrics[k].field;
        if (std::isnan(v)) continue;
        if (std::isnan(best[k]) || (metrics[k].higherIsBetter ? v > best[k] : v < best[k])) best[k] = v;
      }
    }
    for (const auto& r : c.runs) {
      const MetricSummary& s = warmup ? r.metrics.warmup : r.metrics.steady;
      h << "<tr><td class='l'>" << esc(r.label);
      if (s.mean.nonFiniteValues)
        h << " <span title='NaN/Inf output values, counted as 0'>&#9888; " << s.mean.nonFiniteValues << " NaN/Inf</span>";
      h << "</td><td>" << s.frames << "</td>";
      for (size_t k = 0; k < metrics.size(); ++k) {
        const double v = s.mean.*metrics[k].field;
        h << "<td" << (!std::isnan(v) && v == best[k] ? " class='best'" : "") << ">" << metricFormat(metrics[k], v) << "</td>";
      }
      if (!warmup) h << "<td>" << (r.method.empty() ? "&ndash;" : fmt(r.medianTotalMs(), "%.2f")) << "</td>";
      h << "</tr>\n";
    }
    h << "</table>\n";
  };
  h << "<h2>Summary</h2><p class='note'>Means over the frames after warm-up; best value per column in bold. "
       "PSNR, SSIM, FLIP and the temporal errors are computed on tone-mapped sRGB, relMSE and RMSE on linear HDR "
       "radiance. <i>temporal</i> is the mean absolute luma change between consecutive frames (Schied et al. 2017); "
       "<i>temporal vs ref</i> is the mean absolute difference between the result's and the reference's "
       "frame-to-frame change, so a frozen image is not rewarded; <i>ref temporal</i> is the reference's own change.</p>\n";
  summaryTableHtml(false);
  if (c.eval.warmupFrames > 0) {
    h << "<p class='note'>Warm-up frames:</p>\n";
    summaryTableHtml(true);
  }

  // Images of the shown frame: full frames for the slider, enlarged crops side by side.
  std::vector<std::pair<std::string, const Image*>> images;
  for (const auto& r : c.runs) images.emplace_back(r.label, &r.shown);
  images.emplace_back("reference", &c.reference);
  const int zoom = c.cropWidth * 2 <= 520 ? 2 : 1;
  h << "<h2>Frame " << c.shownFrameNumber << "</h2>\n";
  h << "<div class='ctl'>Left: <select id='selA'>";
  for (size_t k = 0; k < images.size(); ++k)
    h << "<option value='" << k << "'" << (k == (images.size() > 2 ? images.size() - 2 : 0) ? " selected" : "") << ">"
      << esc(images[k].first) << "</option>";
  h << "</select> &nbsp; Right: <select id='selB'>";
  for (size_t k = 0; k < images.size(); ++k)
    h << "<option value='" << k << "'" << (k + 1 == images.size() ? " selected" : "") << ">" << esc(images[k].first)
      << "</option>";
  h << "</select> &nbsp; <input type='range' id='sl' min='0' max='100' value='50' aria-label='before/after'></div>\n";
  const int shownWidth = std::min(1300, std::max(c.width, std::min(2 * c.width, 1300)));
  h << "<div class='cmp' style='width:" << shownWidth << "px'><img id='cmpB' alt='right'><div class='top'><img id='cmpA' alt='left'></div>"
    << "<span class='lab' id='labA' style='left:6px'></span><span class='lab' id='labB' style='right:6px'></span></div>\n";

  h << "<h2>Crops (" << c.cropWidth << "&times;" << c.cropHeight << " at " << c.cropX << "," << c.cropY << ", "
    << zoom << "&times;)</h2>\n<div class='strip'>";
  for (const auto& [label, img] : images) {
    h << "<figure><img class='px' width='" << c.cropWidth * zoom << "' height='" << c.cropHeight * zoom << "' src='"
      << dataUri(toneMap(crop(*img, c.cropX, c.cropY, c.cropWidth, c.cropHeight), c.eval.toneMap)) << "' alt='"
      << esc(label) << "'><figcaption>" << esc(label) << "</figcaption></figure>";
  }
  h << "</div>\n";

  h << "<h2>Full frames</h2>\n<div class='strip'>";
  for (size_t k = 0; k < images.size(); ++k)
    h << "<figure><img class='px' id='full-" << k << "' style='max-width:" << std::min(c.width, 440) << "px;width:100%'"
      << " src='" << dataUri(toneMap(*images[k].second, c.eval.toneMap)) << "' alt='" << esc(images[k].first)
      << "'><figcaption>" << esc(images[k].first) << "</figcaption></figure>";
  h << "</div>\n";

  h << "<h2>FLIP error maps (frame " << c.shownFrameNumber << ")</h2>\n"
    << "<p class='note'>LDR-FLIP per pixel against the reference (0 black: no perceived difference, 1 yellow-white: "
       "largest). <svg width='220' height='14'><defs><linearGradient id='mg'>";
  for (int t = 0; t <= 10; ++t) {
    float rgb[3];
    magma(t / 10.0f, rgb);
    char col[16];
    std::snprintf(col, sizeof col, "#%02x%02x%02x", int(rgb[0] * 255 + 0.5f), int(rgb[1] * 255 + 0.5f), int(rgb[2] * 255 + 0.5f));
    h << "<stop offset='" << t * 10 << "%' stop-color='" << col << "'/>";
  }
  h << "</linearGradient></defs><rect width='220' height='14' fill='url(#mg)'/></svg> 0 &rarr; 1</p>\n<div class='strip'>";
  for (const auto& r : c.runs) {
    if (r.flipMap.empty()) continue;
    h << "<figure><img class='px' style='max-width:" << std::min(c.width, 440) << "px;width:100%' src='"
      << dataUri(colorize(r.flipMap)) << "' alt='FLIP " << esc(r.label) << "'><figcaption>" << esc(r.label)
      << ": mean FLIP " << fmt(r.shownFlip, "%.4f") << "</figcaption></figure>";
  }
  h << "</div>\n";

  h << "<h2>Per-frame metrics</h2>\n<div class='plots'>";
  for (const auto& m : metrics) h << plotSvg(c, m);
  h << "</div>\n";

  // Timing per pass.
  std::vector<std::string> passes;
  for (const auto& r : c.runs)
    for (const auto& p : r.passOrder)
      if (std::find(passes.begin(), passes.end(), p) == passes.end()) passes.push_back(p);
  h << "<h2>Timing per pass</h2>\n<p class='note'>Median milliseconds per frame over the frames after warm-up, "
       "as each denoiser's stats() report them (CPU wall time per pass; GPU timestamps on Vulkan).</p>\n";
  h << "<table><tr><th class='l'>run</th><th class='l'>device</th>";
  for (const auto& p : passes) h << "<th>" << esc(p) << "</th>";
  h << "<th>total</th></tr>\n";
  for (const auto& r : c.runs) {
    if (r.method.empty()) continue;
    h << "<tr><td class='l'>" << esc(r.label) << "</td><td class='l'>" << esc(r.device) << "</td>";
    for (const auto& p : passes) h << "<td>" << fmt(r.medianPassMs(p), "%.3f") << "</td>";
    h << "<td>" << fmt(r.medianTotalMs(), "%.3f") << "</td></tr>\n";
  }
  h << "</table>\n";

  h << "<h2>Settings</h2>\n";
  for (const auto& r : c.runs) {
    if (r.method.empty()) continue;
    h << "<details><summary>" << esc(r.label) << "</summary><table>";
    for (const auto& s : r.settings)
      h << "<tr><td class='l'>" << esc(s.name) << "</td><td class='l'>" << esc(s.value) << "</td></tr>";
    h << "</table></details>\n";
  }

  h << "<h2>Metrics</h2>\n<table><tr><th class='l'>metric</th><th class='l'>colour space</th><th class='l'>better</th></tr>";
  for (const auto& m : metrics)
    h << "<tr><td class='l'>" << esc(m.label) << "</td><td class='l'>" << esc(m.space) << "</td><td class='l'>"
      << (m.higherIsBetter ? "higher" : "lower") << "</td></tr>";
  h << "</table>\n<p class='note'>Definitions and constants: docs/evaluation.md.</p>\n";
  h << "<script>" << kScript << "</script>\n</body></html>\n";
  return h.str();
}

}  // namespace rtd::eval
