// Injected into a copy of each built page by tests/test_docs_browser.py and run by headless
// Chromium after the page (and its KaTeX) has rendered.  It writes what it found, as JSON, into a
// pre element (id ca-browser-check) that `chromium --dump-dom` prints.
(function () {
  // TeX left in the text: delimiters, sub/superscripts in braces, common control words.
  var RAW_TEX = /\\\(|\\\)|\\\[|\\\]|\$\$|\^\{|_\{|\\(frac|sqrt|delta|alpha|varepsilon|xi|dot|ddot|mathrm)\b/;

  function inside(node, selector) {
    var el = node.nodeType === 1 ? node : node.parentElement;
    return el !== null && el.closest(selector) !== null;
  }

  function check() {
    var article = document.querySelector("article") || document.body;
    var rawTex = [];
    var walker = document.createTreeWalker(article, NodeFilter.SHOW_TEXT);
    for (var n = walker.nextNode(); n; n = walker.nextNode()) {
      if (inside(n, "pre, .katex, script, style, .md-clipboard")) continue;
      if (RAW_TEX.test(n.nodeValue)) rawTex.push(n.nodeValue.trim().slice(0, 120));
    }
    article.querySelectorAll(".katex-error").forEach(function (el) {
      rawTex.push("KaTeX error: " + (el.getAttribute("title") || "") + " in " + el.textContent.slice(0, 80));
    });
    var arith = article.querySelectorAll(".arithmatex");
    var unrendered = [];
    arith.forEach(function (el) {
      if (el.querySelector(".katex") === null) unrendered.push(el.textContent.slice(0, 120));
    });
    var wide = [];
    article.querySelectorAll("pre > code").forEach(function (code) {
      var pre = code.parentElement;
      var over = code.scrollWidth > code.clientWidth + 1 || pre.scrollWidth > pre.clientWidth + 1;
      if (over) {
        var lines = code.textContent.split("\n");
        var longest = lines.reduce(function (a, b) { return b.length > a.length ? b : a; }, "");
        wide.push({content: code.scrollWidth, box: code.clientWidth, line: longest.slice(0, 120)});
      }
    });
    var images = [], broken = [];
    article.querySelectorAll("img").forEach(function (img) {
      images.push(img.src);
      if (!img.complete || img.naturalWidth === 0) broken.push(img.getAttribute("src"));
    });
    var links = [];
    document.querySelectorAll("a[href]").forEach(function (a) {
      if (a.protocol === "file:") links.push(a.href);
    });
    var out = document.createElement("pre");
    out.id = "ca-browser-check";
    out.textContent = JSON.stringify({
      width: window.innerWidth,
      math: {arithmatex: arith.length, rendered: article.querySelectorAll(".katex").length,
             unrendered: unrendered, raw_tex: rawTex},
      wide_code: wide,
      images: images,
      broken_images: broken,
      links: links
    });
    document.body.appendChild(out);
  }

  window.addEventListener("load", function () { setTimeout(check, 1000); });
})();
