-- Telling a worker's death apart from a job that kills its worker (src/store/sql/queue.rs,
-- recover_expired): the progress the current attempt reported, the best progress when it
-- was claimed, and the worker deaths in a row in which the job got no further.
ALTER TABLE jobs ADD COLUMN attempt_progress REAL NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN claim_progress REAL NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN worker_deaths INTEGER NOT NULL DEFAULT 0;
