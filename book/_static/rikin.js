/* The rikin book's own script (loaded by book/_ext/rikin_book.py).

   A line break may fall between a formula in a line and the punctuation after it, leaving
   a period or a comma alone at the start of the next line. Once MathJax has typeset the
   page, each formula and the punctuation that follows it are kept together. */
(function () {
  "use strict";
  const PUNCTUATION = /^[.,;:)!?]+/;

  function glue() {
    for (const math of document.querySelectorAll("span.math")) {
      const next = math.nextSibling;
      if (!next || next.nodeType !== Node.TEXT_NODE || math.closest(".rikin-nowrap")) {
        continue;
      }
      const found = PUNCTUATION.exec(next.textContent);
      if (!found) {
        continue;
      }
      const keep = document.createElement("span");
      keep.className = "rikin-nowrap";
      keep.style.whiteSpace = "nowrap";
      math.parentNode.insertBefore(keep, math);
      keep.appendChild(math);
      next.textContent = next.textContent.slice(found[0].length);
      keep.appendChild(document.createTextNode(found[0]));
    }
  }

  function start() {
    const mj = window.MathJax;
    if (mj && mj.startup && mj.startup.promise) {
      mj.startup.promise.then(glue);
    } else {
      glue();
    }
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", start);
  } else {
    start();
  }
})();
