import { renderMath } from '../math.js';

renderMath();
document.body.dataset.ready = 'true';
