// What the server says of the site, which the pages' scripts read rather than repeat
// (`web::registry::Site`, in every page's `#estlab-site`): the course a variant belongs
// to unless another is named, and every exercise's texts by its name.
const element = document.getElementById('estlab-site');

/** @type {import('./types/Site').Site} */
export const site = JSON.parse(element.textContent);
