// The self-contained HTML comparison report: every frame of every run as a WebP (or PNG) data
// URI, a frame player with a before/after slider, inline SVG plots and timing bars, and a few
// dozen lines of inline JavaScript. No network resources.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop
#ifdef RTD_HAVE_WEBP
#include <webp/encode.h>
#endif

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "eval/report_plots.h"
#include "rtd/eval/compare.h"

namespace rtd::eval {

namespace {
std::vector<unsigned char> toBytes(const Image& srgb) {
  std::vector<unsigned char> bytes(size_t(srgb.width) * srgb.height * 3);
  for (size_t i = 0; i < size_t(srgb.width) * srgb.height; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = srgb.pixels[i * srgb.channels + std::min(c, srgb.channels - 1)];
      bytes[i * 3 + c] = (unsigned char)std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f);
    }
  return bytes;
}
}  // namespace

std::string encodePng(const Image& srgb) {
  const auto bytes = toBytes(srgb);
  std::string png;
  stbi_write_png_to_func(
      [](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<char*>(data), size_t(size)); },
      &png, srgb.width, srgb.height, 3, bytes.data(), srgb.width * 3);
  return png;
}

std::string encodeReportImage(const Image& srgb, std::string* mime) {
#ifdef RTD_HAVE_WEBP
  const auto bytes = toBytes(srgb);
  uint8_t* out = nullptr;
  const size_t size = WebPEncodeRGB(bytes.data(), srgb.width, srgb.height, srgb.width * 3, 90.0f, &out);
  if (size > 0) {
    std::string webp(reinterpret_cast<const char*>(out), size);
    WebPFree(out);
    if (mime) *mime = "image/webp";
    return webp;
  }
  WebPFree(out);  // encoding failed (e.g. a side above 16383): PNG instead
#endif
  if (mime) *mime = "image/png";
  return encodePng(srgb);
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

using report::esc;
using report::fmt;

/// A JavaScript string literal of a data URI.
std::string uri(const std::string& mime, const std::string& bytes) {
  return "\"data:" + mime + ";base64," + base64(bytes) + "\"";
}

std::string jsNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string jsString(const std::string& s) {
  std::string o = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') o += '\\';
    if (ch == '<') {
      o += "\\u003c";  // never "</script>" inside the script
      continue;
    }
    o += ch;
  }
  return o + "\"";
}

const char* kStyle = R"(
*{box-sizing:border-box}
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:0 auto;padding:16px 20px;color:#222;background:#fff;max-width:1400px}
h1{font-size:24px;margin:0 0 6px} h2{font-size:19px;margin:26px 0 8px;border-bottom:1px solid #ddd;padding-bottom:4px}
.meta{color:#555;font-size:14px;line-height:1.5}
.wrap{max-width:100%;overflow-x:auto}
table{border-collapse:collapse;font-size:13px;margin:6px 0} th,td{border:1px solid #ccc;padding:3px 7px;text-align:right}
th{background:#f3f3f3;font-weight:600} td.l,th.l{text-align:left} td.best{font-weight:bold;background:#e6f4e6}
th.info,td.info{color:#777;background:#fafafa}
.note{font-size:13px;color:#444;max-width:1000px;line-height:1.45}
.box{border:1px solid #d8d2bf;background:#fbf8ef;padding:8px 12px;font-size:13px;line-height:1.5;max-width:1000px}
.player{position:sticky;top:0;z-index:5;background:rgba(255,255,255,.96);border-bottom:1px solid #ddd;padding:6px 0;
  display:flex;flex-wrap:wrap;gap:6px 14px;align-items:center;font-size:14px}
.player input[type=range]{width:min(420px,60vw);vertical-align:middle} .player button{min-width:64px}
.cmp{position:relative;line-height:0;border:1px solid #888;max-width:100%;margin-top:8px}
.cmp img{display:block;width:100%;height:auto;image-rendering:pixelated}
.cmp .top{position:absolute;left:0;top:0;width:100%;height:100%}
.cmp .lab{position:absolute;top:6px;background:rgba(0,0,0,.6);color:#fff;font-size:12px;line-height:1.4;padding:1px 6px}
.rows{display:grid;grid-template-columns:repeat(3,minmax(0,1fr));gap:10px 10px}
figure{margin:0;min-width:0} figcaption{font-size:12px;color:#333;margin-top:2px;overflow-wrap:anywhere}
figure img{display:block;width:100%;height:auto;image-rendering:pixelated;border:1px solid #bbb}
.crops{display:flex;flex-wrap:wrap;gap:10px}
.crop{image-rendering:pixelated;border:1px solid #bbb;background-repeat:no-repeat}
.legend{display:flex;flex-wrap:wrap;gap:4px 16px;font-size:13px;margin:4px 0} .legend i{display:inline-block;width:12px;height:12px;margin-right:5px;vertical-align:-1px}
.plots{display:grid;grid-template-columns:repeat(2,minmax(0,1fr));gap:8px}
svg.plot{width:100%;height:auto;display:block} .pt{font-size:13px;font-weight:600} .tk{font-size:11px;fill:#444} .wl{font-size:11px;fill:#8a6d2b}
svg.plot circle{cursor:pointer} svg.plot circle:hover{stroke:#000;stroke-width:2}
svg.plot .cur{stroke:#000;stroke-dasharray:3 3}
svg.bars{width:100%;height:auto;display:block} svg.bars rect:hover{stroke:#000}
details{margin:6px 0} summary{cursor:pointer;font-size:14px}
)";

// The player: frame slider, play/pause, view (image or FLIP), the before/after slider, the rows
// of run | reference | FLIP, the crops and the current-frame line of every plot.
const char* kScript = R"(
(function(){
 var D=window.RTD,N=D.frames.length,cur=D.start,timer=null,$=function(i){return document.getElementById(i);};
 var fs=$('frame'),fl=$('frameLabel'),sa=$('selA'),sb=$('selB'),split=$('split'),view=$('view');
 function stream(k){return k<D.runs.length?D.runs[k]:D.ref;}
 function src(k,kind){var s=stream(k);var a=kind=='flip'&&s.flip&&s.flip.length?s.flip:s.img;return a[cur];}
 function show(){
  fl.textContent=(cur+1)+' / '+N+' (frame '+D.frames[cur]+(cur<D.warmup?', warm-up':'')+')';
  var v=view.value;
  $('cmpA').src=src(+sa.value,v);$('cmpB').src=src(+sb.value,v);
  $('labA').textContent=sa.options[sa.selectedIndex].text;$('labB').textContent=sb.options[sb.selectedIndex].text;
  document.querySelectorAll('img[data-s]').forEach(function(im){im.src=src(+im.dataset.s,im.dataset.k);});
  document.querySelectorAll('[data-m]').forEach(function(e){var r=D.runs[+e.dataset.s],x=r.m[e.dataset.m];
    e.textContent=x&&x[cur]!=null?(+x[cur]).toPrecision(4):'\u2013';});
  document.querySelectorAll('.crop').forEach(function(c){c.style.backgroundImage='url('+src(+c.dataset.s,'img')+')';});
  document.querySelectorAll('svg.plot').forEach(function(g){var l=g.querySelector('.cur');if(!l)return;
    var f0=+g.dataset.f0,f1=+g.dataset.f1,x0=+g.dataset.x0,x1=+g.dataset.x1,f=D.frames[cur];
    var x=f1>f0?x0+(f-f0)/(f1-f0)*(x1-x0):(x0+x1)/2;l.setAttribute('x1',x);l.setAttribute('x2',x);});
 }
 function go(i){cur=(i%N+N)%N;fs.value=cur;show();}
 function clip(){$('cmpA').parentNode.style.clipPath='inset(0 '+(100-split.value)+'% 0 0)';}
 function play(){if(timer){clearInterval(timer);timer=null;$('play').textContent='play';return;}
  $('play').textContent='pause';timer=setInterval(function(){go(cur+1);},1000/+$('fps').value);}
 fs.max=N-1;fs.addEventListener('input',function(){go(+fs.value);});
 [sa,sb,view].forEach(function(e){e.addEventListener('change',show);});
 split.addEventListener('input',clip);$('play').addEventListener('click',play);
 $('prev').addEventListener('click',function(){go(cur-1);});$('next').addEventListener('click',function(){go(cur+1);});
 $('fps').addEventListener('change',function(){if(timer){play();play();}});
 document.addEventListener('keydown',function(e){if(e.target.tagName=='SELECT')return;
  if(e.key=='ArrowRight')go(cur+1);else if(e.key=='ArrowLeft')go(cur-1);else if(e.key==' '){e.preventDefault();play();}});
 document.querySelectorAll('svg.plot circle[data-f]').forEach(function(c){c.addEventListener('click',function(){
  var i=D.frames.indexOf(+c.dataset.f);if(i>=0)go(i);});});
 go(cur);clip();
})();
)";

/// Runs with a method, in order (not the input).
std::vector<const MethodRun*> methodRuns(const Comparison& c) {
  std::vector<const MethodRun*> out;
  for (const auto& r : c.runs)
    if (!r.method.empty()) out.push_back(&r);
  return out;
}

void summaryTable(std::ostringstream& h, const Comparison& c, bool warmup) {
  const auto& metrics = metricList();
  h << "<div class='wrap'><table><tr><th class='l'>run</th><th>frames</th>";
  for (const auto& m : metrics)
    h << "<th" << (m.ranked ? "" : " class='info'") << " title='" << esc(m.space)
      << (m.ranked ? (m.higherIsBetter ? "; higher is better" : "; lower is better") : "; information, not ranked") << "'>"
      << esc(m.label) << (m.ranked ? (m.higherIsBetter ? " &uarr;" : " &darr;") : "") << "</th>";
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
      const auto& m = metrics[k];
      const double v = s.mean.*m.field;
      h << "<td class='" << (!m.ranked ? "info" : !std::isnan(v) && v == best[k] ? "best" : "") << "' title='mean over "
        << esc(coverage(s)) << "; median " << formatMetric(m, s.median.*m.field) << ", quartiles "
        << formatMetric(m, s.q1.*m.field) << " to " << formatMetric(m, s.q3.*m.field) << "'>" << formatMetric(m, v) << "</td>";
    }
    if (!warmup) h << "<td>" << (r.method.empty() ? "&ndash;" : fmt(r.medianTotalMs(), "%.2f")) << "</td>";
    h << "</tr>\n";
  }
  h << "</table></div>\n";
}

void referenceQualityBox(std::ostringstream& h, const Comparison& c) {
  const ReferenceQuality& q = c.referenceQuality;
  h << "<div class='box'><b>Reference.</b> ";
  if (q.exact) {
    h << "Exact (computed in closed form): the metrics measure the error to the true image.";
  } else {
    h << (q.spp > 0 ? std::to_string(q.spp) + " samples per pixel. " : std::string("Sample count unknown. "));
    if (q.estimated)
      h << "Its own remaining noise, estimated from two independent half-sample references A and B (the variance "
           "of their mean is E[(A&minus;B)&sup2;]/4): relMSE " << fmt(q.relMse, "%.3g") << ", PSNR "
        << fmt(q.psnr, "%.1f") << " dB (means over the frames after warm-up). A result whose error approaches "
           "these is limited by the reference, and a blurrier result can score better than a sharper one.";
    else
      h << "Its remaining noise is not known (no half-sample references): small differences between methods may be "
           "the reference's own noise.";
  }
  if (!q.note.empty()) h << " " << esc(q.note);
  h << "</div>\n";
}

/// Settings that differ between the runs of one method: a table per method with several runs.
void settingsSection(std::ostringstream& h, const Comparison& c) {
  const auto runs = methodRuns(c);
  std::vector<std::string> methods;
  for (const auto* r : runs)
    if (std::find(methods.begin(), methods.end(), r->method) == methods.end()) methods.push_back(r->method);
  for (const auto& m : methods) {
    std::vector<const MethodRun*> same;
    for (const auto* r : runs)
      if (r->method == m) same.push_back(r);
    if (same.size() < 2) continue;
    std::vector<std::string> differing;
    for (const auto& s : same.front()->settings)
      for (const auto* r : same)
        for (const auto& t : r->settings)
          if (t.name == s.name && t.value != s.value && std::find(differing.begin(), differing.end(), s.name) == differing.end())
            differing.push_back(s.name);
    h << "<p class='note'>Settings in which the " << esc(m) << " runs differ:</p><div class='wrap'><table><tr><th class='l'>setting</th>";
    for (const auto* r : same) h << "<th class='l'>" << esc(r->label) << "</th>";
    h << "</tr>";
    for (const auto& name : differing) {
      h << "<tr><td class='l'>" << esc(name) << "</td>";
      for (const auto* r : same)
        for (const auto& t : r->settings)
          if (t.name == name) h << "<td class='l'>" << esc(t.value) << "</td>";
      h << "</tr>";
    }
    if (differing.empty()) h << "<tr><td class='l' colspan='" << same.size() + 1 << "'>none (they run on different backends)</td></tr>";
    h << "</table></div>\n";
  }
  for (const auto* r : runs) {
    h << "<details><summary>" << esc(r->label) << " (" << esc(r->device) << "): every setting</summary><table>";
    for (const auto& s : r->settings)
      h << "<tr><td class='l'>" << esc(s.name) << "</td><td class='l'>" << esc(s.value) << "</td></tr>";
    h << "</table></details>\n";
  }
}

}  // namespace

std::string comparisonHtml(const Comparison& c) {
  const auto& metrics = metricList();
  const size_t nRuns = c.runs.size(), ref = nRuns;  // stream index of the reference
  const MetricSummary& steady0 = c.runs.empty() ? MetricSummary{} : c.runs.front().metrics.steady;
  const MetricSummary& warm0 = c.runs.empty() ? MetricSummary{} : c.runs.front().metrics.warmup;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><meta name='viewport' content='width=device-width'>"
    << "<title>" << esc(c.title) << "</title><style>" << kStyle << "</style></head><body>\n";
  h << "<h1>" << esc(c.title) << "</h1>\n<div class='meta'>Source: " << esc(c.source) << "<br>" << c.width << "&times;"
    << c.height << ", " << c.frames << " frames. Headline means over " << esc(coverage(steady0)) << "; the first "
    << c.eval.warmupFrames << " frame(s) are warm-up (history still filling), averaged separately"
    << (warm0.frames ? " (" + esc(coverage(warm0)) + ")" : std::string()) << ". Tone map for the display-referred metrics: "
    << esc(operatorName(c.eval.toneMap.op)) << ", exposure " << fmt(c.eval.toneMap.exposure, "%.2f")
    << " stops, then sRGB encoding. FLIP at " << fmt(c.eval.flip.pixelsPerDegree(), "%.1f")
    << " pixels per degree.<br>Machine: " << esc(c.machine) << ". Total time " << fmt(c.seconds, "%.1f")
    << " s (denoising and evaluation).";
  for (const auto& note : c.skipped) h << "<br>Skipped: " << esc(note);
  h << "</div>\n";
  referenceQualityBox(h, c);

  h << "<h2>Summary</h2><p class='note'>Means over " << esc(coverage(steady0))
    << " (hover a value for its median and quartiles over the frames); best value per ranked column in bold. "
       "PSNR, SSIM, FLIP and the temporal columns are computed on tone-mapped sRGB, HDR-FLIP, relMSE and RMSE on "
       "linear HDR radiance. <i>temporal vs ref</i> is the mean absolute difference between the result's and the "
       "reference's frame-to-frame luma change, so a frozen image is not rewarded; <i>temporal change</i> and "
       "<i>ref temporal change</i> (grey) are the raw mean luma change of the result and of the reference, shown as "
       "information only.</p>\n";
  summaryTable(h, c, false);
  if (c.eval.warmupFrames > 0) {
    h << "<details><summary>Means over the warm-up, " << esc(coverage(warm0)) << "</summary>\n";
    summaryTable(h, c, true);
    h << "</details>\n";
  }

  // ---- Frames: the player.
  const bool haveFlip = std::any_of(c.runs.begin(), c.runs.end(), [](const MethodRun& r) { return !r.flipImages.empty(); });
  h << "<h2>Frames</h2>\n<p class='note'>Every frame of every run. The slider compares any two (left of the split: "
       "the first). Keys: &larr; &rarr; step, space plays. Images are tone-mapped as the metrics are"
    << (c.displayWidth < c.width ? " and stored at " + std::to_string(c.displayWidth) + "&times;" + std::to_string(c.displayHeight) : std::string())
    << "; a FLIP map shows LDR-FLIP per pixel (black 0: no perceived difference, yellow-white 1).</p>\n";
  h << "<div class='player'><button id='prev'>&larr;</button><button id='play'>play</button><button id='next'>&rarr;</button>"
       "<input type='range' id='frame' min='0' value='0' aria-label='frame'><span id='frameLabel'></span>"
       "<label>fps <select id='fps'><option>2</option><option>4</option><option selected>8</option><option>15</option>"
       "<option>30</option></select></label><label>show <select id='view'><option value='img'>images</option>"
    << (haveFlip ? "<option value='flip'>FLIP maps</option>" : "") << "</select></label></div>\n";
  h << "<div class='player' style='position:static;border:0'>Left: <select id='selA'>";
  const auto streamLabel = [&](size_t k) { return k < nRuns ? c.runs[k].label : std::string("reference"); };
  const size_t defaultA = nRuns > 1 ? nRuns - 1 : 0;
  for (size_t k = 0; k <= nRuns; ++k)
    h << "<option value='" << k << "'" << (k == defaultA ? " selected" : "") << ">" << esc(streamLabel(k)) << "</option>";
  h << "</select> Right: <select id='selB'>";
  for (size_t k = 0; k <= nRuns; ++k)
    h << "<option value='" << k << "'" << (k == ref ? " selected" : "") << ">" << esc(streamLabel(k)) << "</option>";
  h << "</select> split <input type='range' id='split' min='0' max='100' value='50' aria-label='before/after'></div>\n";
  // The split view at the largest whole multiple of the stored size that fits the page (1360 px
  // of content), so that small frames are enlarged with square pixels.
  const int stored = std::max(1, c.displayWidth > 0 ? c.displayWidth : c.width);
  const int cmpWidth = stored * std::max(1, 1360 / stored);
  h << "<div class='cmp' style='width:" << cmpWidth << "px'><img id='cmpB' alt='right'><div class='top'><img id='cmpA' alt='left'></div>"
    << "<span class='lab' id='labA' style='left:6px'></span><span class='lab' id='labB' style='right:6px'></span></div>\n";

  // Rows: each run beside the reference, then its FLIP map; frame values under each.
  h << "<h2>Each run beside the reference</h2>\n<div class='rows'>";
  for (size_t k = 0; k < nRuns; ++k) {
    const auto& r = c.runs[k];
    h << "<figure><img data-s='" << k << "' data-k='img' alt='" << esc(r.label) << "'><figcaption><b>" << esc(r.label)
      << "</b>: PSNR <span data-s='" << k << "' data-m='psnr'></span> dB, SSIM <span data-s='" << k
      << "' data-m='ssim'></span></figcaption></figure>";
    h << "<figure><img data-s='" << ref << "' data-k='img' alt='reference'><figcaption>reference</figcaption></figure>";
    if (!r.flipImages.empty())
      h << "<figure><img data-s='" << k << "' data-k='flip' alt='FLIP " << esc(r.label) << "'><figcaption>FLIP of "
        << esc(r.label) << ": mean <span data-s='" << k << "' data-m='flip'></span>, median <span data-s='" << k
        << "' data-m='flipMedian'></span></figcaption></figure>";
    else
      h << "<figure></figure>";
  }
  h << "</div>\n";

  // Crops, enlarged, from the same per-frame images.
  // Crops enlarged by a whole factor to about 250 px wide (five fit a row), at least 1x.
  const int zoom = std::max(1, 250 / std::max(1, c.cropWidth));
  const double cw = c.cropWidth * zoom, ch = c.cropHeight * zoom, px = c.cropX * zoom, py = c.cropY * zoom;
  h << "<h2>Crops (" << c.cropWidth << "&times;" << c.cropHeight << " at " << c.cropX << "," << c.cropY << ", " << zoom
    << "&times;)</h2>\n<div class='crops'>";
  for (size_t k = 0; k <= nRuns; ++k)
    h << "<figure><div class='crop' data-s='" << k << "' style='width:" << fmt(cw, "%.0f") << "px;height:" << fmt(ch, "%.0f")
      << "px;background-size:" << fmt(c.width * zoom, "%.0f") << "px " << fmt(c.height * zoom, "%.0f")
      << "px;background-position:-" << fmt(px, "%.0f") << "px -" << fmt(py, "%.0f") << "px'></div><figcaption>"
      << esc(streamLabel(k)) << "</figcaption></figure>";
  h << "</div>\n";

  // ---- Plots.
  h << "<h2>Per-frame metrics</h2>\n" << report::legend(c) << "<div class='plots'>";
  for (const auto& m : metrics) h << report::metricPlot(c, m);
  h << "</div>\n";

  // ---- Timing.
  h << "<h2>Timing per pass</h2>\n<p class='note'>Median milliseconds per frame of each pass over the frames after "
       "warm-up, as each denoiser's stats() reports them (CPU wall time per pass; GPU timestamps on Vulkan), stacked; "
       "the figure after each bar is the median total per frame.</p>\n"
    << report::timingBars(c);
  h << "<details><summary>The same as a table</summary><div class='wrap'><table><tr><th class='l'>pass</th>";
  const auto runs = methodRuns(c);
  for (const auto* r : runs) h << "<th>" << esc(r->label) << "</th>";
  h << "</tr>";
  for (const auto& p : report::passNames(c)) {
    h << "<tr><td class='l'>" << esc(p) << "</td>";
    for (const auto* r : runs) h << "<td>" << fmt(r->medianPassMs(p), "%.3f") << "</td>";
    h << "</tr>";
  }
  h << "<tr><td class='l'><b>median total</b></td>";
  for (const auto* r : runs) h << "<td><b>" << fmt(r->medianTotalMs(), "%.3f") << "</b></td>";
  h << "</tr><tr><td class='l'>device</td>";
  for (const auto* r : runs) h << "<td>" << esc(r->device) << "</td>";
  h << "</tr></table></div></details>\n";

  h << "<h2>Settings</h2>\n";
  settingsSection(h, c);

  h << "<h2>Metrics</h2>\n<table><tr><th class='l'>metric</th><th class='l'>colour space</th><th class='l'>better</th></tr>";
  for (const auto& m : metrics)
    h << "<tr><td class='l'>" << esc(m.label) << "</td><td class='l'>" << esc(m.space) << "</td><td class='l'>"
      << (!m.ranked ? "information" : m.higherIsBetter ? "higher" : "lower") << "</td></tr>";
  h << "</table>\n<p class='note'>Definitions and constants: docs/evaluation.md.</p>\n";

  // ---- The data: every frame's images and values.
  h << "<script>window.RTD={start:" << c.shownFrame << ",warmup:" << c.eval.warmupFrames << ",frames:[";
  for (size_t i = 0; i < c.frameNumbers.size(); ++i) h << (i ? "," : "") << c.frameNumbers[i];
  h << "],runs:[";
  for (size_t k = 0; k < nRuns; ++k) {
    const auto& r = c.runs[k];
    h << (k ? ",\n" : "\n") << "{label:" << jsString(r.label) << ",img:[";
    for (size_t i = 0; i < r.frameImages.size(); ++i) h << (i ? "," : "") << uri(c.imageMime, r.frameImages[i]);
    h << "],flip:[";
    for (size_t i = 0; i < r.flipImages.size(); ++i) h << (i ? "," : "") << uri(c.imageMime, r.flipImages[i]);
    h << "],m:{";
    bool first = true;
    const auto series = [&](const std::string& key, auto value) {
      h << (first ? "" : ",") << key << ":[";
      first = false;
      for (size_t i = 0; i < r.metrics.frames.size(); ++i) h << (i ? "," : "") << jsNumber(value(r.metrics.frames[i]));
      h << "]";
    };
    for (const auto& m : metrics) series(m.key, [&](const FrameMetrics& f) { return f.*m.field; });
    series("flipMedian", [](const FrameMetrics& f) { return f.flipPixels.median; });
    h << "}}";
  }
  h << "],\nref:{img:[";
  for (size_t i = 0; i < c.referenceImages.size(); ++i) h << (i ? "," : "") << uri(c.imageMime, c.referenceImages[i]);
  h << "]}};</script>\n<script>" << kScript << "</script>\n</body></html>\n";
  return h.str();
}

}  // namespace rtd::eval
