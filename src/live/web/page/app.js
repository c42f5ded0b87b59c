// The live picture and the score: the MJPEG stream and one server-sent event per frame.
'use strict';
const token = new URLSearchParams(location.search).get('token');
const withToken = (path) => (token ? `${path}?token=${encodeURIComponent(token)}` : path);
document.getElementById('picture').src = withToken('stream.mjpg');
const meter = document.getElementById('meter');
const events = new EventSource(withToken('events'));
events.onmessage = (e) => {
  const s = JSON.parse(e.data);
  meter.textContent = `frame ${s.frame}  ${s.metric} ${s.score.toPrecision(5)}  ` +
    `${s.percent_of_peak.toFixed(1)} % of peak  ${s.trend}`;
};
