// Sets data-figures-loaded / data-figures-failed on <body> once the page has loaded: the window's
// load event waits for every <img> (loaded or failed), after which naturalWidth > 0 tells a decoded
// image from a broken one. (img.decode() promises are not used: under headless Chromium's virtual
// time they may settle after the budget.)
(function () {
  function report() {
    var imgs = Array.prototype.slice.call(document.images), ok = 0, bad = [];
    imgs.forEach(function (img) {
      if (img.complete && img.naturalWidth > 0) { ok += 1; }
      else { var f = img.closest('figure'); bad.push(f ? f.id : img.alt); }
    });
    document.body.dataset.figuresTotal = String(imgs.length);
    document.body.dataset.figuresLoaded = String(ok);
    document.body.setAttribute('data-figures-failed', String(bad.length));
    if (bad.length) { document.body.setAttribute('data-figures-failed-ids', bad.join(' ')); }
  }
  if (document.readyState === 'complete') { report(); } else { window.addEventListener('load', report); }
})();
