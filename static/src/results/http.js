// The API as the pages call it: JSON in and out, a refusal thrown with the server's own
// reason, and a submission read until the server has graded it.

/** @typedef {import('../types/Submission').Submission} Submission */

/** @param {number} ms */
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** A refusal or failure of the API: the server's `error` text and the HTTP status. */
export class ApiError extends Error {
  /**
   * @param {string} message
   * @param {number} status
   */
  constructor(message, status) {
    super(message);
    this.status = status;
  }
}

/**
 * GETs `url` as JSON; an answer other than 2xx throws an ApiError with the server's
 * `error`. The caller names the answer's type, one of the server's in `types/`, in a
 * JSDoc `@type` where it keeps the answer.
 *
 * @param {string} url
 * @param {RequestInit} [options]
 * @returns {Promise<any>}
 */
export async function getJson(url, options) {
  const response = await fetch(url, options);
  if (!response.ok) {
    /** @type {Partial<import('../types/ErrorBody').ErrorBody>} */
    const body = await response.json().catch(() => ({}));
    throw new ApiError(body.error ?? `${response.status} ${response.statusText}`, response.status);
  }
  return response.json().catch(() => ({}));
}

/**
 * POSTs `body` as JSON; an answer other than 2xx throws an ApiError with the server's
 * `error`.
 *
 * @param {string} url
 * @param {unknown} body
 * @returns {Promise<any>}
 */
export function postJson(url, body) {
  return getJson(url, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  });
}

/**
 * The submission at `url` (its API path) once graded; `onUpdate` gets it each time it is
 * read, graded or not.
 *
 * @param {string} url
 * @param {(submission: Submission) => void} [onUpdate]
 * @returns {Promise<Submission>}
 */
export async function pollSubmission(url, onUpdate = () => {}, interval = 500) {
  for (;;) {
    /** @type {Submission} */
    const submission = await getJson(url);
    onUpdate(submission);
    if (submission.status === 'graded') return submission;
    await sleep(interval);
  }
}
