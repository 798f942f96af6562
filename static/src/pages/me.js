// The signed-in person's page: times in the reader's own time zone, and the latest
// submission's result in full, as the workbench shows a server's result (waiting for its
// grade when it is not graded yet).
import { percent } from '../results/format.js';
import { getJson, pollSubmission } from '../results/http.js';
import { element, renderSubmission } from '../results/render.js';

function localize(root) {
  for (const time of root.querySelectorAll('time[datetime]')) {
    const at = new Date(time.dateTime);
    if (!Number.isNaN(at.getTime()) && !time.title) {
      time.title = time.textContent;
      time.textContent = at.toLocaleString(undefined, { dateStyle: 'medium', timeStyle: 'short' });
    }
  }
}

const statusWords = { queued: 'waiting', grading: 'being graded', graded: 'graded' };
const score = (share) => (share === null || share === undefined ? '–' : percent(share));

/** The history's row of `submission`, as the server would write it now. */
function updateRow(section, submission) {
  const row = section.querySelector(`table.history tr[data-id="${submission.id}"]`);
  if (!row) return;
  const cells = row.querySelectorAll('td');
  cells[2].textContent = statusWords[submission.status] ?? submission.status;
  cells[3].textContent = score(submission.score);
  cells[5].textContent = score(submission.final_score);
}

/** The score that counts, once a submission that was waiting is graded. */
async function updateCounting(section) {
  const lab = section.dataset.lab;
  /** @type {import('../types/About').About} */
  const about = await getJson('/api/me');
  const assignment = about.assignments.find((a) => a.lab === lab);
  const counting = section.querySelector('.counting .value');
  if (assignment && counting) counting.textContent = score(assignment.counting_score);
}

/** Fills a `.latest` box with its submission's result; resolves once it is first shown. */
async function showLatest(box) {
  const id = box.dataset.submission;
  const section = box.closest('section.assignment') ?? document;
  const heading = element('h4', null, `Your latest submission (${id})`);
  const result = element('div', 'submission');
  box.replaceChildren(heading, result);
  const url = `/api/submissions/${encodeURIComponent(id)}`;
  try {
    /** @type {import('../types/Submission').Submission} */
    const submission = await getJson(url);
    renderSubmission(result, submission, { open: true });
    if (submission.status !== 'graded') {
      // Graded in a moment: shown when it is, with the row and the score that counts.
      pollSubmission(url, (during) => renderSubmission(result, during, { open: true }), 1000)
        .then((graded) => {
          updateRow(section, graded);
          return updateCounting(section);
        })
        .catch((error) => {
          result.dataset.status = 'failed';
          result.replaceChildren(element('p', 'verdict', `Submission ${id}: ${error.message}`));
        });
    }
  } catch (error) {
    result.dataset.status = 'failed';
    result.replaceChildren(element('p', 'verdict', `Submission ${id} could not be read: ${error.message}`));
  }
}

localize(document);
await Promise.all([...document.querySelectorAll('.latest[data-submission]')].map(showLatest));
document.body.dataset.ready = 'true';
