// The API as the pages call it: JSON in and out, a refusal thrown with the server's own
// reason, and a submission read until the server has graded it.

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

/** A refusal or failure of the API: the server's `error` text and the HTTP status. */
export class ApiError extends Error {
  constructor(message, status) {
    super(message);
    this.status = status;
  }
}

/** GETs `url` as JSON; an answer other than 2xx throws an ApiError with the server's `error`. */
export async function getJson(url, options) {
  const response = await fetch(url, options);
  const body = await response.json().catch(() => ({}));
  if (!response.ok) throw new ApiError(body.error ?? `${response.status} ${response.statusText}`, response.status);
  return body;
}

/** POSTs `body` as JSON; an answer other than 2xx throws an ApiError with the server's `error`. */
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
 */
export async function pollSubmission(url, onUpdate = () => {}, interval = 500) {
  for (;;) {
    const submission = await getJson(url);
    onUpdate(submission);
    if (submission.status === 'graded') return submission;
    await sleep(interval);
  }
}
