// The page's routes: #/session/ID (one pane) and #/compare/ID1/ID2 (two panes side by side).

export function parseRoute(hash: string): string[] {
  const parts = hash.replace(/^#\/?/, '').split('/').filter(Boolean).map(decodeURIComponent);
  if (parts[0] === 'session' && parts[1]) return [parts[1]];
  if (parts[0] === 'compare' && parts[1] && parts[2]) return [parts[1], parts[2]];
  return [];
}

export function routeFor(ids: string[]): string {
  if (ids.length === 0) return '#/';
  if (ids.length === 1) return `#/session/${encodeURIComponent(ids[0])}`;
  return `#/compare/${encodeURIComponent(ids[0])}/${encodeURIComponent(ids[1])}`;
}
