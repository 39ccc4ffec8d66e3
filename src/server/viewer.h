/* viewer.h — the GET /viewer route: the embedded single-page viewer of stored meshes
 * (pan and zoom over their tiles, values under the cursor). */
#ifndef TC_SERVER_VIEWER_H
#define TC_SERVER_VIEWER_H

#include "server/reply.h"
#include "server/routes.h"

void tc_viewer(const tc_route_input *in, tc_reply *out);

#endif
