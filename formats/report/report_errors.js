window.napkinReportError = function (message) {
  var box = document.createElement('div');
  box.className = 'napkin-' + 'script-error';
  box.textContent = 'report script error: ' + message;
  (document.body || document.documentElement).appendChild(box);
};
window.addEventListener('error', function (e) {
  window.napkinReportError(e.message + ' (' + e.filename + ':' + e.lineno + ')');
});
window.addEventListener('unhandledrejection', function (e) { window.napkinReportError(String(e.reason)); });
