// Typeset the formulas that pymdownx.arithmatex (generic mode) leaves as \( ... \) and \[ ... \],
// with the KaTeX shipped beside this file (docs/assets/katex/, no network needed).
document$.subscribe(function (page) {
  renderMathInElement(page.body, {
    delimiters: [
      {left: "\\(", right: "\\)", display: false},
      {left: "\\[", right: "\\]", display: true}
    ],
    throwOnError: false
  });
});
