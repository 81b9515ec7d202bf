// The warning line for a filter that looks degraded or lost (EngineStats.tracking): null while it
// looks fine, and for a server that does not say.
import type { EngineStats } from '../net/protocol';

export interface TrackingWarning {
  level: 'degraded' | 'lost';
  text: string;
}

export function trackingWarning(st: EngineStats): TrackingWarning | null {
  if (st.tracking !== 'degraded' && st.tracking !== 'lost') return null;
  const what = st.tracking === 'lost' ? 'Filter likely lost' : 'Filter tracking degraded';
  return { level: st.tracking, text: st.tracking_reason ? `${what}: ${st.tracking_reason}` : what };
}
