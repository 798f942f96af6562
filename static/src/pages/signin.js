// The sign-in page. A sign-in link carries the code after '#', which browsers never send
// to a server (nor to a log or a Referer): this fills the field with it, takes it out of
// the address bar, and leaves the click on "Sign in" to the person.
const field = /** @type {HTMLInputElement | null} */ (document.getElementById('code'));
const fromLink = decodeURIComponent(window.location.hash.slice(1)).trim();
if (field && fromLink) {
  field.value = fromLink;
  history.replaceState(null, '', window.location.pathname);
  document.getElementById('from-link').hidden = false;
  document.getElementById('sign-in').focus();
}
document.body.dataset.ready = 'true';
